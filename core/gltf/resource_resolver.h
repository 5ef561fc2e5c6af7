// Where a glTF file's `uri`s may be read from. A uri is untrusted input: a resolver only ever
// returns bytes from the places a request is allowed to name (the scene's own folder, or the
// files uploaded with a job). `data:` URIs are decoded by the loader and never reach a resolver.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace partita {

class ResourceResolver {
  public:
    virtual ~ResourceResolver() = default;
    /// The bytes of the resource a (percent-decoded, relative) uri names, or an error message in
    /// `error` and nullopt when it is not allowed or does not exist.
    virtual std::optional<std::vector<uint8_t>> read(const std::string& uri,
                                                     std::string& error) const = 0;
};

/// Reads files inside one folder only: no absolute paths, no `..` escape, no scheme, and no
/// symlink that resolves outside the folder.
class FolderResolver : public ResourceResolver {
  public:
    explicit FolderResolver(std::filesystem::path root, uint64_t maxFileBytes = uint64_t(1) << 30);
    std::optional<std::vector<uint8_t>> read(const std::string& uri,
                                             std::string& error) const override;

  private:
    std::filesystem::path root_;  // canonical
    uint64_t maxFileBytes_;
};

/// Serves resources uploaded with a job, by the relative name they were uploaded under.
class MemoryResolver : public ResourceResolver {
  public:
    explicit MemoryResolver(std::map<std::string, std::vector<uint8_t>> files)
        : files_(std::move(files)) {}
    std::optional<std::vector<uint8_t>> read(const std::string& uri,
                                             std::string& error) const override;

  private:
    std::map<std::string, std::vector<uint8_t>> files_;
};

/// Shared check used by both resolvers: a uri that is a plain relative path with no `..`
/// component, no scheme, no backslash, no NUL. Returns an empty string or the reason it is refused.
std::string checkRelativeUri(const std::string& uri);

/// `uri` made safe for a one-line message: control bytes become '?', long names are cut.
std::string printableUri(const std::string& uri);

}  // namespace partita
