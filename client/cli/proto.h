// The generated service contract. The build generates it either under its package path
// (partita/v1/partita.grpc.pb.h) or flat (partita.grpc.pb.h) depending on how protoc is given
// the import path; both work.
#pragma once

#if __has_include("partita/v1/partita.grpc.pb.h")
#include "partita/v1/partita.grpc.pb.h"
#include "partita/v1/partita.pb.h"
#else
#include "partita.grpc.pb.h"
#include "partita.pb.h"
#endif
