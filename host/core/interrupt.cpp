#include "core/interrupt.h"

#include <pthread.h>
#include <signal.h>

#include <chrono>
#include <cstdlib>
#include <thread>

namespace pcl {

namespace {
std::atomic<bool> gStop{false};
std::atomic<bool> gGraceful{true};
}  // namespace

const std::atomic<bool>& watchInterrupts(bool graceful) {
    static std::atomic<bool> started{false};
    gStop.store(false);
    gGraceful.store(graceful);
    if (started.exchange(true)) return gStop;
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
    std::thread([set] {
        std::chrono::steady_clock::time_point first;
        for (bool pressed = false;;) {
            int sig = 0;
            if (sigwait(&set, &sig) != 0) continue;
            const auto now = std::chrono::steady_clock::now();
            if (!gGraceful.load() || (pressed && now - first > std::chrono::seconds(1))) std::_Exit(128 + sig);
            if (!pressed) first = now;
            pressed = true;
            gStop.store(true);
        }
    }).detach();
    return gStop;
}

}  // namespace pcl
