// Runs the real photoncl binary (PHOTONCL_BINARY) with arguments, for the command-line tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace photoncl_cli {

struct Result {
    int status = -1;
    std::string output;  // stdout and stderr together
};

// `ENV photoncl ARGS 2>&1`: the exit status (-1 if it did not exit normally) and everything
// printed. env: shell variable assignments for this run only ("NAME=value ..."), or empty.
inline Result run(const std::string& args, const std::string& env = "") {
    std::string cmd = (env.empty() ? "" : env + " ") + std::string(PHOTONCL_BINARY) + " " + args + " 2>&1";
    Result r;
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return r;
    std::array<char, 4096> buf;
    while (size_t n = fread(buf.data(), 1, buf.size(), pipe)) r.output.append(buf.data(), n);
    int raw = pclose(pipe);
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return r;
}

}  // namespace photoncl_cli
