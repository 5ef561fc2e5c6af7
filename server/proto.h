// The generated service contract. protobuf_generate places the files either under the proto's
// package path or flat in the output folder depending on how the proto target is set up; this
// header hides which. Never include an OpenImageIO header in a file that includes this one
// (DESIGN.md: the two do not compile in one translation unit).
#pragma once

#if __has_include("partita/v1/partita.grpc.pb.h")
#include "partita/v1/partita.grpc.pb.h"
#include "partita/v1/partita.pb.h"
#else
#include "partita.grpc.pb.h"
#include "partita.pb.h"
#endif

namespace partita::server {
namespace pb = ::partita::v1;
}  // namespace partita::server
