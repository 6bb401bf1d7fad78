#include "scene/json_parse.h"

#include <fstream>
#include <sstream>

#include "scene/scene_error.h"

namespace pcl {

namespace {
struct TooDeep {};
}  // namespace

nlohmann::json parseSceneJson(const std::string& text, const std::string& file) {
    // The parser callback sees the depth of every value as it is opened; throwing aborts the
    // parse before the document grows any deeper.
    auto limitDepth = [](int depth, nlohmann::json::parse_event_t event, nlohmann::json&) {
        if (depth > kMaxJsonDepth && (event == nlohmann::json::parse_event_t::object_start ||
                                      event == nlohmann::json::parse_event_t::array_start))
            throw TooDeep{};
        return true;
    };
    try {
        return nlohmann::json::parse(text, limitDepth);
    } catch (const TooDeep&) {
        failInput(file, "", "JSON nested at most " + std::to_string(kMaxJsonDepth) + " levels deep", "deeper nesting");
    } catch (const nlohmann::json::exception& e) {
        // Drop nlohmann's "[json.exception.parse_error.101] " prefix; keep line and column.
        std::string what = e.what();
        auto close = what.find("] ");
        if (what.rfind("[json.exception", 0) == 0 && close != std::string::npos) what = what.substr(close + 2);
        failInput(file, "", "valid JSON", what);
    }
}

std::string readTextFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open file for reading (missing or unreadable)");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw InputError(path + ": read error");
    return text.str();
}

std::string showJson(const nlohmann::json& value) {
    std::string s = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
}

}  // namespace pcl
