// 64-bit FNV-1a, the hash of scenes, settings and shard files: it catches mix-ups and damage
// (a flipped bit, a truncated file), not forgery. Fast enough for a 4K shard (~265 MB) in about
// a second.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace pcl {

struct Fnv1a {
    uint64_t h = 14695981039346656037ull;
    void add(const void* data, size_t bytes) {
        const unsigned char* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < bytes; ++i) {
            h ^= p[i];
            h *= 1099511628211ull;
        }
    }
    void add(const std::string& s) { add(s.data(), s.size()); }
};

// 16 lower-case hex digits.
inline std::string hex64(uint64_t v) {
    static const char* digits = "0123456789abcdef";
    std::string s(16, '0');
    for (int i = 15; i >= 0; --i, v >>= 4) s[size_t(i)] = digits[v & 15];
    return s;
}

// Parses hex64's form; false if `s` is not 1..16 hex digits.
inline bool parseHex64(const std::string& s, uint64_t& out) {
    if (s.empty() || s.size() > 16) return false;
    out = 0;
    for (char c : s) {
        int d = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
        if (d < 0) return false;
        out = out << 4 | uint64_t(d);
    }
    return true;
}

}  // namespace pcl
