#include "shard/shard_files.h"

#include <cstring>
#include <stdexcept>

#include "byte_stream.h"
#include "compression.h"
#include "params/job_parameters.h"

namespace partita {

namespace {

constexpr uint32_t kPlanMagic = 0x4e4c5050;    // "PPLN"
constexpr uint32_t kResultMagic = 0x44485350;  // "PSHD"
constexpr uint32_t kPlanVersion = 5;    // 2: settings as named parameters; 3: partition patterns;
                                        // 4: the direct-light partition; 5: each one's move
constexpr uint32_t kResultVersion = 3;  // 2: films compressed (zlib); 3: with zstd (compression.h)

// The plan's settings: the budget, then every declared parameter of the job (shared and the
// algorithm's, defaults filled in) as its name and its text (formatParameter, which reads back
// exactly), so that a setting added to a declaration travels without a change here.
void putSettings(ByteWriter& w, const std::string& algorithm, const RenderSettings& s) {
    w.put(uint8_t(s.budgetKind));
    w.put(s.budget);
    std::vector<JobParameter> parameters = jobParameters(registeredAlgorithm(algorithm), s);
    std::erase_if(parameters, [](const JobParameter& p) {
        return std::holds_alternative<std::monostate>(p.value);
    });
    w.put(uint32_t(parameters.size()));
    for (const JobParameter& p : parameters) {
        w.putString(p.spec->name);
        w.putString(formatParameter(*p.spec, p.value));
    }
}

RenderSettings getSettings(ByteReader& r, const std::string& algorithm) {
    RenderSettings s;
    uint8_t kind = r.get<uint8_t>();
    if (kind > uint8_t(BudgetKind::Seconds)) r.fail("bad budget kind");
    s.budgetKind = BudgetKind(kind);
    s.budget = r.get<double>();
    ParameterValues values;
    uint32_t count = r.get<uint32_t>();
    for (uint32_t i = 0; i < count; ++i) {
        std::string name = r.getString();
        values.set(name, r.getString());
    }
    const AlgorithmRegistry::Entry* entry = nullptr;
    try {
        entry = &registeredAlgorithm(algorithm);
    } catch (const std::invalid_argument& e) {
        r.fail(e.what());
    }
    if (std::string why = applyJobParameters(*entry, values, s); !why.empty()) r.fail(why);
    return s;
}

}  // namespace

uint64_t fileChecksum(std::span<const uint8_t> bytes) {
    // FNV-1a's multiply-xor over 8-byte words (then the tail byte by byte), with a final
    // avalanche: a shard file is hundreds of MB, and byte-wise FNV-1a took a second per GB.
    // A checksum against truncation and damage, not against an adversary.
    uint64_t h = 0xcbf29ce484222325ull ^ bytes.size();
    size_t i = 0;
    for (; i + 8 <= bytes.size(); i += 8) {
        uint64_t word;
        std::memcpy(&word, bytes.data() + i, 8);
        h = (h ^ word) * 0x100000001b3ull;
        h ^= h >> 29;
    }
    for (; i < bytes.size(); ++i) h = (h ^ bytes[i]) * 0x100000001b3ull;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    return h ^ (h >> 33);
}

std::vector<uint8_t> serializeShardPlan(const ShardPlan& p) {
    ByteWriter w;
    w.putHeader(kPlanMagic, kPlanVersion);
    w.putString(p.algorithm);
    w.putString(p.scene);
    w.put(p.sceneDigest);
    putSettings(w, p.algorithm, p.settings);
    w.put(p.shards);
    w.putBytes(p.state);
    return std::move(w.bytes);
}

ShardPlan deserializeShardPlan(std::span<const uint8_t> bytes) {
    ByteReader r(bytes, "shard plan");
    r.expectHeader(kPlanMagic, kPlanVersion, "shard plan");
    ShardPlan p;
    p.algorithm = r.getString();
    p.scene = r.getString();
    p.sceneDigest = r.get<uint64_t>();
    p.settings = getSettings(r, p.algorithm);
    p.shards = r.get<uint32_t>();
    if (p.shards == 0) r.fail("no shards");
    p.state = r.getBytes();
    if (!r.atEnd()) r.fail("trailing bytes");
    return p;
}

uint64_t ShardPlan::id() const { return fileChecksum(serializeShardPlan(*this)); }

namespace {

void putWork(ByteWriter& w, const ShardWork& work, int threads) {
    w.put(uint64_t(work.films.size()));
    for (const Film& f : work.films) {
        // The film's bytes (its size, then compressed with their length, as putBytes): fed to
        // the compressor tile by tile, straight into the result's bytes.
        std::vector<std::vector<uint8_t>> pieces = f.serializePieces(threads);
        uint64_t size = 0;
        for (const auto& p : pieces) size += p.size();
        w.put(size);
        const size_t lengthAt = w.bytes.size();
        w.put(uint64_t(0));
        const uint64_t length = appendCompressed(w.bytes, pieces);
        std::memcpy(w.bytes.data() + lengthAt, &length, sizeof length);
    }
    w.put(uint64_t(work.counts.size()));
    for (uint64_t c : work.counts) w.put(c);
    w.put(uint64_t(work.sums.size()));
    for (const auto& [name, value] : work.sums) {
        w.putString(name);
        w.put(value);
    }
}

}  // namespace

// The body, then its fileChecksum: a truncated or flipped file fails the check before anything
// in it is trusted.
std::vector<uint8_t> serializeShardResult(const ShardResult& s, int threads) {
    ByteWriter w;
    w.putHeader(kResultMagic, kResultVersion);
    w.put(s.planId);
    w.put(s.shard);
    w.put(s.shards);
    putWork(w, s.work, threads);
    w.put(fileChecksum(w.bytes));
    return std::move(w.bytes);
}

ShardResult deserializeShardResult(std::span<const uint8_t> bytes, int threads) {
    ByteReader r(bytes, "shard result");
    r.expectHeader(kResultMagic, kResultVersion, "shard result");
    if (bytes.size() < 16) r.fail("truncated");
    uint64_t stored;
    std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
    if (fileChecksum(bytes.first(bytes.size() - 8)) != stored)
        r.fail("checksum mismatch (truncated or damaged file)");
    ShardResult s;
    s.checksum = stored;
    ByteReader body(bytes.first(bytes.size() - 8), "shard result");
    body.get<uint32_t>();
    body.get<uint32_t>();
    s.planId = body.get<uint64_t>();
    s.shard = body.get<uint32_t>();
    s.shards = body.get<uint32_t>();
    if (s.shards == 0 || s.shard >= s.shards) body.fail("bad shard index");
    uint64_t films = body.get<uint64_t>();
    for (uint64_t i = 0; i < films; ++i) {
        const uint64_t size = body.get<uint64_t>();
        std::vector<uint8_t> film;
        try {
            film = decompressBytes(body.getRaw(body.get<uint64_t>()), size);  // in place
        } catch (const std::invalid_argument& e) {
            body.fail(e.what());
        }
        s.work.films.push_back(Film::deserialize(film, threads));
    }
    uint64_t counts = body.get<uint64_t>();
    for (uint64_t i = 0; i < counts; ++i) s.work.counts.push_back(body.get<uint64_t>());
    uint64_t sums = body.get<uint64_t>();
    for (uint64_t i = 0; i < sums; ++i) {
        std::string name = body.getString();
        s.work.sums[name] = body.get<double>();
    }
    if (!body.atEnd()) body.fail("trailing bytes");
    return s;
}

uint64_t shardResultChecksum(const ShardResult& result) {
    if (result.checksum != 0) return result.checksum;
    const std::vector<uint8_t> bytes = serializeShardResult(result);
    uint64_t stored;
    std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
    return stored;
}

}  // namespace partita
