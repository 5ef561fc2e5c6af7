// FetchResult: streams one result file in 1 MiB chunks, reading the next chunk only when the
// previous one has been written (memory stays at one chunk however large the file).
#pragma once

#include <grpcpp/grpcpp.h>

#include <filesystem>

#include "proto.h"

namespace partita::server {

constexpr size_t kResultChunkBytes = size_t(1) << 20;

/// A reactor that sends `file`; it finishes with `status` right away when that is not OK, and
/// with INTERNAL when the file cannot be read. Deletes itself when done.
/// Chunks are serialized ResultChunk messages (the service's methods are raw).
grpc::ServerWriteReactor<grpc::ByteBuffer>* makeResultStream(const std::filesystem::path& file,
                                                             const grpc::Status& status);

}  // namespace partita::server
