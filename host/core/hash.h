// 64-bit FNV-1a (http://www.isthe.com/chongo/tech/comp/fnv/), the one hash of the project: kernel
// binary cache keys and entries, scenes, settings and shard files. It catches mix-ups and damage
// (a flipped bit, a truncated file), not forgery. Fast enough for a 4K shard (~265 MB) in about
// a second.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace pcl {

struct Fnv1a {
    static constexpr uint64_t kOffsetBasis = 14695981039346656037ull;  // 0xcbf29ce484222325
    uint64_t h = kOffsetBasis;
    void add(const void* data, size_t bytes) {
        const unsigned char* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < bytes; ++i) {
            h ^= p[i];
            h *= 1099511628211ull;
        }
    }
    void add(const std::string& s) { add(s.data(), s.size()); }
};

// FNV-1a of `size` bytes, continuing from `hash` (the offset basis by default).
inline uint64_t fnv1a64(const void* data, size_t size, uint64_t hash = Fnv1a::kOffsetBasis) {
    Fnv1a f;
    f.h = hash;
    f.add(data, size);
    return f.h;
}

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
