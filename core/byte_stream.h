// A little-endian-as-the-host binary writer and a bounds-checked reader, shared by the versioned
// file formats (chain plans, films, shard plans and shard results). The reader throws
// std::invalid_argument("<what>: truncated") instead of reading past the end.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace partita {

class ByteWriter {
  public:
    template <typename T>
    void put(const T& value) {
        static_assert(std::is_trivially_copyable_v<T>);
        // resize + memcpy rather than a range insert: the same bytes, and GCC 12 sees no
        // (false) -Wstringop-overflow in it.
        const size_t at = bytes.size();
        bytes.resize(at + sizeof value);
        std::memcpy(bytes.data() + at, &value, sizeof value);
    }
    /// A length (uint64) and the bytes.
    void putBytes(std::span<const uint8_t> b) {
        put(uint64_t(b.size()));
        bytes.insert(bytes.end(), b.begin(), b.end());
    }
    void putString(const std::string& s) {
        putBytes({reinterpret_cast<const uint8_t*>(s.data()), s.size()});
    }
    /// A file format's magic number and version, first in every file (ByteReader::expectHeader).
    void putHeader(uint32_t magic, uint32_t version) {
        put(magic);
        put(version);
    }
    /// Signed values value(i), i in [0, count), as zigzag LEB128 varints (small magnitudes of
    /// either sign in few bytes: 7 bits a byte), written through a pointer after one resize
    /// (byte by byte, a film's ~10^8 varints took seconds).
    template <typename Value>
    void putSignedVarints(size_t count, Value&& value) {
        constexpr size_t kMaxVarintBytes = 10;
        const size_t at = bytes.size();
        bytes.resize(at + count * kMaxVarintBytes);
        uint8_t* p = bytes.data() + at;
        for (size_t i = 0; i < count; ++i) {
            const int64_t s = value(i);
            uint64_t v = (uint64_t(s) << 1) ^ uint64_t(s >> 63);
            while (v >= 0x80) {
                *p++ = uint8_t(v | 0x80);
                v >>= 7;
            }
            *p++ = uint8_t(v);
        }
        bytes.resize(size_t(p - bytes.data()));
    }
    /// Raw bytes, no length.
    void putRaw(const void* data, size_t size) {
        const auto* p = static_cast<const uint8_t*>(data);
        bytes.insert(bytes.end(), p, p + size);
    }
    std::vector<uint8_t> bytes;
};

class ByteReader {
  public:
    ByteReader(std::span<const uint8_t> b, std::string what) : bytes_(b), what_(std::move(what)) {}
    template <typename T>
    T get() {
        static_assert(std::is_trivially_copyable_v<T>);
        need(sizeof(T));
        T value;
        std::memcpy(&value, bytes_.data() + at_, sizeof value);
        at_ += sizeof value;
        return value;
    }
    std::vector<uint8_t> getBytes() {
        std::span<const uint8_t> s = getRaw(get<uint64_t>());
        return {s.begin(), s.end()};
    }
    std::string getString() {
        std::span<const uint8_t> s = getRaw(get<uint64_t>());
        return {reinterpret_cast<const char*>(s.data()), s.size()};
    }
    /// Reads putHeader's fields: fails with "not a Partita <kind>" or "<kind> version N, this
    /// build reads M".
    void expectHeader(uint32_t magic, uint32_t version, const std::string& kind) {
        if (get<uint32_t>() != magic) fail("not a Partita " + kind);
        if (uint32_t v = get<uint32_t>(); v != version)
            fail(kind + " version " + std::to_string(v) + ", this build reads " +
                 std::to_string(version));
    }
    /// store(i, v) for the next `count` zigzag varints v (putSignedVarints); fails on a varint
    /// of more than 64 bits or past the end. Read through a local pointer (through the members,
    /// a film's ~10^8 varints took seconds).
    template <typename Store>
    void getSignedVarints(size_t count, Store&& store) {
        const uint8_t* p = bytes_.data() + at_;
        const uint8_t* const end = bytes_.data() + bytes_.size();
        for (size_t i = 0; i < count; ++i) {
            uint64_t v = 0;
            for (int shift = 0;; shift += 7) {
                if (shift >= 64) fail("bad varint");
                if (p == end) fail("truncated");
                const uint8_t b = *p++;
                v |= uint64_t(b & 0x7f) << shift;
                if (!(b & 0x80)) break;
            }
            store(i, int64_t(v >> 1) ^ -int64_t(v & 1));
        }
        at_ = size_t(p - bytes_.data());
    }
    /// The next `n` bytes, in place.
    std::span<const uint8_t> getRaw(uint64_t n) {
        need(n);
        std::span<const uint8_t> s = bytes_.subspan(at_, size_t(n));
        at_ += size_t(n);
        return s;
    }
    bool atEnd() const { return at_ == bytes_.size(); }
    /// Throws "<what>: <message>".
    [[noreturn]] void fail(const std::string& message) const {
        throw std::invalid_argument(what_ + ": " + message);
    }

  private:
    void need(uint64_t n) const {
        if (n > bytes_.size() - at_) fail("truncated");
    }
    std::span<const uint8_t> bytes_;
    std::string what_;
    size_t at_ = 0;
};

}  // namespace partita
