// One preview frame of a job, shared by all its watchers. The render hands over float images;
// the PNGs are encoded the first time a watcher is about to send the frame (on a service thread,
// never a render thread), once for all watchers. A slow watcher that skips frames never makes
// anyone encode them.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <grpcpp/support/byte_buffer.h>

#include "image.h"
#include "proto.h"

namespace partita::server {

class PreviewFrameData {
  public:
    /// A frame held in memory (previews during the render, and the final image).
    PreviewFrameData(uint64_t sequence, bool final, LayeredImage image);
    /// The final frame of a finished job, read back from its result EXR when a watcher asks.
    PreviewFrameData(uint64_t sequence, std::filesystem::path resultExr);

    uint64_t sequence() const { return sequence_; }
    /// Seconds its PNGs took to encode (0 until a watcher has asked for them).
    double encodeSeconds() const { return encodeSeconds_.load(); }
    bool isFinal() const { return final_; }

    /// The frame as sent: layer "combined" first, then one per type layer, each an sRGB PNG with
    /// the combined image's automatic exposure; with `raw`, also the float32 pixels. Thread-safe.
    /// Throws std::runtime_error when a frame on disk cannot be read.
    pb::PreviewFrame encode(bool raw) const;

    /// The frame as a serialized JobEvent of job `jobId` (encode(raw), then wire.h). Watchers
    /// sending the same frame at the same time share one buffer, so a stalled watcher holds no
    /// bytes of its own beyond a reference. Implemented in preview_frame_wire.cpp.
    std::shared_ptr<const grpc::ByteBuffer> wireEvent(const std::string& jobId, bool raw) const;

  private:
    std::shared_ptr<const LayeredImage> image() const;  // loads a disk-backed frame

    uint64_t sequence_;
    bool final_;
    std::shared_ptr<const LayeredImage> image_;  // null for a disk-backed frame
    std::filesystem::path exr_;
    mutable std::mutex mutex_;
    mutable std::optional<std::vector<std::string>> pngs_;  // cached encoding (in-memory frames)
    mutable std::atomic<double> encodeSeconds_{0};
    // The serialized event while some watcher still sends it, [0] PNG only, [1] with raw pixels.
    mutable std::weak_ptr<const grpc::ByteBuffer> wire_[2];
};

}  // namespace partita::server
