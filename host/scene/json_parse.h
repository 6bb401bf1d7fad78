// Parsing scene text into nlohmann::json with a nesting limit. nlohmann's parser is iterative,
// but copying, dumping and tinygltf's extras walker recurse; a file nested 100 000 deep must fail
// with a message, not overflow the stack, so depth is capped while parsing.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace pcl {

constexpr int kMaxJsonDepth = 64;

// Parses `text`; throws InputError naming `file` on malformed JSON, numbers out of range
// (1e999) or nesting deeper than kMaxJsonDepth.
nlohmann::json parseSceneJson(const std::string& text, const std::string& file);

// Reads a whole file; throws InputError naming it when it cannot be read.
std::string readTextFile(const std::string& path);

// A JSON value for messages: compact, cut to about 60 characters.
std::string showJson(const nlohmann::json& value);

}  // namespace pcl
