#include "wire.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/wire_format_lite.h>
#include <grpcpp/impl/codegen/proto_utils.h>
#include <grpcpp/support/proto_buffer_reader.h>
#include <grpcpp/support/proto_buffer_writer.h>

#include <vector>

#include "text.h"

namespace partita::server {

namespace {

namespace gp = google::protobuf;
using gp::internal::WireFormatLite;

constexpr int kMaxDepth = 32;

/// The dotted path of the first string field whose bytes are not UTF-8 in the message `in` is
/// positioned at, or "" when there is none (or the bytes are malformed: the caller says so).
std::string firstInvalidUtf8(gp::io::CodedInputStream& in, const gp::Descriptor* type, int depth) {
    if (depth > kMaxDepth) return {};
    for (;;) {
        uint32_t tag = in.ReadTag();
        if (tag == 0) return {};
        const gp::FieldDescriptor* field =
            type->FindFieldByNumber(WireFormatLite::GetTagFieldNumber(tag));
        bool delimited =
            WireFormatLite::GetTagWireType(tag) == WireFormatLite::WIRETYPE_LENGTH_DELIMITED;
        bool text = field && field->type() == gp::FieldDescriptor::TYPE_STRING;
        bool message = field && field->type() == gp::FieldDescriptor::TYPE_MESSAGE;
        if (!delimited || !(text || message)) {
            if (!WireFormatLite::SkipField(&in, tag)) return {};
            continue;
        }
        uint32_t length = 0;
        if (!in.ReadVarint32(&length)) return {};
        if (text) {
            std::string value;
            if (!in.ReadString(&value, int(length))) return {};
            if (!isValidUtf8(value)) return field->name();
            continue;
        }
        auto limit = in.PushLimit(int(length));
        std::string inner = firstInvalidUtf8(in, field->message_type(), depth + 1);
        if (!inner.empty()) return field->name() + "." + inner;
        in.PopLimit(limit);
    }
}

void fixString(gp::Message& m, const gp::Reflection& r, const gp::FieldDescriptor* f, int i) {
    std::string scratch;
    const std::string& value = i < 0 ? r.GetStringReference(m, f, &scratch)
                                     : r.GetRepeatedStringReference(m, f, i, &scratch);
    if (isValidUtf8(value)) return;
    std::string fixed = toValidUtf8(value);
    if (i < 0)
        r.SetString(&m, f, std::move(fixed));
    else
        r.SetRepeatedString(&m, f, i, std::move(fixed));
}

}  // namespace

grpc::Status parseRequest(const grpc::ByteBuffer& wire, gp::Message& out) {
    {
        grpc::ByteBuffer copy(wire);  // the reader consumes its buffer; copies share the slices
        grpc::ProtoBufferReader reader(&copy);
        if (out.ParseFromZeroCopyStream(&reader)) return grpc::Status::OK;
    }
    grpc::ByteBuffer copy(wire);
    grpc::ProtoBufferReader reader(&copy);
    gp::io::CodedInputStream in(&reader);
    std::string field = firstInvalidUtf8(in, out.GetDescriptor(), 0);
    if (!field.empty())
        return {grpc::StatusCode::INVALID_ARGUMENT,
                "request field '" + field +
                    "' is not valid UTF-8 (protobuf string fields must be UTF-8 text)"};
    return {grpc::StatusCode::INVALID_ARGUMENT,
            "malformed request: not a valid " + out.GetDescriptor()->full_name() + " message"};
}

bool allStringsValid(const gp::Message& m) {
    const gp::Reflection& r = *m.GetReflection();
    std::vector<const gp::FieldDescriptor*> fields;
    r.ListFields(m, &fields);
    std::string scratch;
    for (const gp::FieldDescriptor* f : fields) {
        int n = f->is_repeated() ? r.FieldSize(m, f) : 1;
        for (int i = 0; i < n; ++i) {
            if (f->type() == gp::FieldDescriptor::TYPE_STRING) {
                const std::string& v = f->is_repeated()
                                           ? r.GetRepeatedStringReference(m, f, i, &scratch)
                                           : r.GetStringReference(m, f, &scratch);
                if (!isValidUtf8(v)) return false;
            } else if (f->cpp_type() == gp::FieldDescriptor::CPPTYPE_MESSAGE) {
                const gp::Message& sub =
                    f->is_repeated() ? r.GetRepeatedMessage(m, f, i) : r.GetMessage(m, f);
                if (!allStringsValid(sub)) return false;
            }
        }
    }
    return true;
}

void makeStringsValidUtf8(gp::Message& m) {
    // Read-only first: mutable access to a map field through reflection rebuilds it.
    if (allStringsValid(m)) return;
    const gp::Reflection& r = *m.GetReflection();
    std::vector<const gp::FieldDescriptor*> fields;
    r.ListFields(m, &fields);
    for (const gp::FieldDescriptor* f : fields) {
        if (f->type() == gp::FieldDescriptor::TYPE_STRING) {
            if (!f->is_repeated())
                fixString(m, r, f, -1);
            else
                for (int i = 0; i < r.FieldSize(m, f); ++i) fixString(m, r, f, i);
        } else if (f->cpp_type() == gp::FieldDescriptor::CPPTYPE_MESSAGE) {
            if (!f->is_repeated())
                makeStringsValidUtf8(*r.MutableMessage(&m, f));
            else
                for (int i = 0; i < r.FieldSize(m, f); ++i)
                    makeStringsValidUtf8(*r.MutableRepeatedMessage(&m, f, i));
        }
    }
}

grpc::ByteBuffer serialize(gp::Message& message) {
    makeStringsValidUtf8(message);
    grpc::ByteBuffer wire;
    bool own = false;  // GenericSerialize's flag; the ByteBuffer owns its slices either way
    grpc::Status s =
        grpc::GenericSerialize<grpc::ProtoBufferWriter, gp::Message>(message, &wire, &own);
    if (!s.ok()) throw std::runtime_error("cannot serialize a response: " + s.error_message());
    return wire;
}

}  // namespace partita::server
