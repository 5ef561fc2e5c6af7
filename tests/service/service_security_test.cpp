// Security defaults: scene names and glTF uris cannot reach files outside the scene root or the
// upload; a token is required when configured; a non-loopback address needs TLS + token or an
// explicit --insecure.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "service_client.h"

namespace partita::test {
namespace {

using namespace std::chrono_literals;
using Code = grpc::StatusCode;

const fs::path kScenes = PARTITA_SCENES_DIR;

/// Submits, waits for the end, returns the final job.
pb::Job runToEnd(pb::Partita::Stub& stub, const pb::JobSpec& spec) {
    Submitted job = submit(stub, spec);
    EXPECT_TRUE(job.status.ok()) << job.status.error_message();
    return job.status.ok() ? waitForEnd(stub, job.id) : pb::Job{};
}

/// A copy of the cornell scene as <dir>/<name>.gltf + cornell.bin.
void copyCornell(const fs::path& dir, const std::string& name) {
    fs::create_directories(dir);
    fs::copy_file(kScenes / "cornell" / "cornell.gltf", dir / (name + ".gltf"));
    fs::copy_file(kScenes / "cornell" / "cornell.bin", dir / "cornell.bin");
}

TEST(ServiceSecurity, SceneNamesCannotTraverse) {
    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    for (const std::string& name : std::vector<std::string>{
             "../x", "..", "/etc/passwd", "cornell/../cornell", "cornell/cornell.gltf", ".",
             ".hidden", "a\\b", std::string("cor\0nell", 8)}) {
        pb::JobSpec spec = sceneSpec(name, 8, 8, 1);
        Submitted r = submit(*stub, spec);
        EXPECT_EQ(r.status.error_code(), Code::INVALID_ARGUMENT)
            << name << ": " << r.status.error_message();
    }
}

TEST(ServiceSecurity, SymlinksAndUrisOutOfTheSceneRootAreRefused) {
    TempDir dir;
    fs::path root = dir / "root", outside = dir / "outside";
    copyCornell(root / "good", "good");
    copyCornell(outside / "evil", "evil");
    fs::create_directory_symlink(outside / "evil", root / "evil");  // a scene folder linking out
    fs::create_directories(root / "link");
    fs::create_symlink(outside / "evil" / "evil.gltf",
                       root / "link" / "link.gltf");  // a file linking out
    // A scene inside the root whose buffer uri climbs out to a valid buffer.
    fs::create_directories(root / "escape");
    std::string gltf = readFile(kScenes / "cornell" / "cornell.gltf");
    size_t at = gltf.find("\"cornell.bin\"");
    ASSERT_NE(at, std::string::npos);
    gltf.replace(at, 13, "\"../../outside/evil/cornell.bin\"");
    writeFile(root / "escape" / "escape.gltf", gltf);

    TempDir store;
    Daemon daemon(store.path(), {}, root);
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();

    pb::ListScenesResponse scenes;
    auto ctx = context();
    ASSERT_TRUE(stub->ListScenes(ctx.get(), {}, &scenes).ok());
    std::vector<std::string> names;
    for (const auto& s : scenes.scenes()) names.push_back(s.name());
    EXPECT_EQ(names, (std::vector<std::string>{"escape", "good"}));

    EXPECT_EQ(runToEnd(*stub, sceneSpec("good", 8, 8, 1)).state(), pb::JOB_STATE_DONE);
    for (const std::string name : {"evil", "link"}) {
        Submitted r = submit(*stub, sceneSpec(name, 8, 8, 1));
        EXPECT_EQ(r.status.error_code(), Code::INVALID_ARGUMENT) << name;
        EXPECT_NE(r.status.error_message().find("outside the scene root"), std::string::npos)
            << r.status.error_message();
    }
    pb::Job escaped = runToEnd(*stub, sceneSpec("escape", 8, 8, 1));
    EXPECT_EQ(escaped.state(), pb::JOB_STATE_FAILED)
        << "the buffer outside the scene folder must not be read";
    EXPECT_NE(escaped.error().find("refused"), std::string::npos) << escaped.error();
}

TEST(ServiceSecurity, UploadedGltfUrisOutsideTheUploadFailTheJob) {
    TempDir dir;
    // A valid 36-byte triangle buffer on disk: had the daemon read it, the job would succeed.
    std::string triangle(36, '\0');
    float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::memcpy(triangle.data(), v, 36);
    writeFile(dir / "triangle.bin", triangle);

    TempDir store;
    Daemon daemon(store.path());
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    for (const std::string& uri : std::vector<std::string>{
             "../../etc/passwd", "/etc/passwd", (dir / "triangle.bin").string(),
             "file://" + (dir / "triangle.bin").string(), "missing.bin"}) {
        pb::JobSpec spec;
        spec.mutable_scene()->mutable_gltf()->set_gltf(gltfWithBufferUri(uri));
        spec.set_width(8);
        spec.set_height(8);
        pb::Job end = runToEnd(*stub, spec);
        EXPECT_EQ(end.state(), pb::JOB_STATE_FAILED) << uri;
        EXPECT_FALSE(end.error().empty());
        EXPECT_EQ(end.error().find("root:"), std::string::npos) << "no file content in messages";
        std::printf("uri %s -> %s\n", uri.c_str(), end.error().c_str());
    }
    // The same glTF with its buffer uploaded under that name renders.
    pb::JobSpec good;
    good.mutable_scene()->mutable_gltf()->set_gltf(gltfWithBufferUri("triangle.bin"));
    auto* r = good.mutable_scene()->mutable_gltf()->add_resources();
    r->set_uri("triangle.bin");
    r->set_data(triangle);
    good.set_width(8);
    good.set_height(8);
    EXPECT_EQ(runToEnd(*stub, good).state(), pb::JOB_STATE_DONE);
}

TEST(ServiceSecurity, TokenIsRequiredWhenConfigured) {
    TempDir dir;
    writeFile(dir / "token", "s3cret-token\n");
    TempDir store;
    Daemon daemon(store.path(), {"--token-file", (dir / "token").string()});
    ASSERT_TRUE(daemon.running());
    auto stub = daemon.stub();
    for (const std::string token : {"", "wrong", "s3cret-toke", "s3cret-token-and-more"}) {
        pb::ServerInfo info;
        auto ctx = context(10s, token);
        grpc::Status s = stub->GetServerInfo(ctx.get(), {}, &info);
        EXPECT_EQ(s.error_code(), Code::UNAUTHENTICATED) << "token '" << token << "'";
        EXPECT_EQ(submit(*stub, sceneSpec("cornell", 8, 8, 1), token).status.error_code(),
                  Code::UNAUTHENTICATED);
    }
    {
        auto ctx = context(10s);
        ctx->AddMetadata("authorization", "s3cret-token");  // no "Bearer"
        pb::ServerInfo info;
        EXPECT_EQ(stub->GetServerInfo(ctx.get(), {}, &info).error_code(), Code::UNAUTHENTICATED);
    }
    pb::ServerInfo info;
    auto ctx = context(10s, "s3cret-token");
    ASSERT_TRUE(stub->GetServerInfo(ctx.get(), {}, &info).ok());
    Submitted job = submit(*stub, sceneSpec("cornell", 8, 8, 1), "s3cret-token");
    ASSERT_TRUE(job.status.ok());
    // Streams check the token too.
    EXPECT_EQ(watch(*stub, job.id).status.error_code(), Code::UNAUTHENTICATED);
    EXPECT_EQ(fetch(*stub, job.id, pb::RESULT_KIND_EXR).status.error_code(), Code::UNAUTHENTICATED);
    auto wctx = context(60s, "s3cret-token");
    auto reader = stub->WatchJob(wctx.get(), watchRequest(job.id));
    pb::JobEvent event;
    pb::JobState last = pb::JOB_STATE_UNSPECIFIED;
    while (reader->Read(&event))
        if (event.has_state()) last = event.state().state();
    EXPECT_TRUE(reader->Finish().ok());
    EXPECT_EQ(last, pb::JOB_STATE_DONE);
}

TEST(ServiceSecurity, NonLoopbackNeedsTlsAndTokenOrInsecure) {
    TempDir store;
    auto [code, log] = runPartitad({"--listen", "0.0.0.0:0", "--store", store.path().string()});
    EXPECT_NE(code, 0);
    EXPECT_NE(log.find("non-loopback"), std::string::npos) << log;
    EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << "one clear line: " << log;

    TempDir dir;
    writeFile(dir / "token", "tok\n");
    auto [code2, log2] = runPartitad({"--listen", "0.0.0.0:0", "--store", store.path().string(),
                                      "--token-file", (dir / "token").string()});
    EXPECT_NE(code2, 0) << "a token without TLS is not enough";
    EXPECT_NE(log2.find("non-loopback"), std::string::npos) << log2;

    auto [code3, log3] =
        runPartitad({"--listen", "[::1]:0", "--store", store.path().string(), "--tls-cert", "x"});
    EXPECT_NE(code3, 0);
    EXPECT_NE(log3.find("--tls-key"), std::string::npos) << log3;

    Daemon insecure(store.path(), {"--listen", "0.0.0.0:0", "--insecure"});
    ASSERT_TRUE(insecure.running()) << "--insecure allows it explicitly";
    pb::ServerInfo info;
    auto ctx = context(10s);
    EXPECT_TRUE(insecure.stub()->GetServerInfo(ctx.get(), {}, &info).ok());
}

TEST(ServiceSecurity, TlsWithTokenOnAnyAddress) {
    TempDir dir;
    std::string cmd =
        "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=localhost -addext "
        "subjectAltName=DNS:localhost,IP:127.0.0.1 -keyout " +
        (dir / "key.pem").string() + " -out " + (dir / "cert.pem").string() + " >/dev/null 2>&1";
    if (std::system(cmd.c_str()) != 0)
        GTEST_SKIP() << "openssl is not available to make a test certificate";
    writeFile(dir / "token", "tls-token");
    TempDir store;
    Daemon daemon(store.path(),
                  {"--listen", "0.0.0.0:0", "--tls-cert", (dir / "cert.pem").string(), "--tls-key",
                   (dir / "key.pem").string(), "--token-file", (dir / "token").string()});
    ASSERT_TRUE(daemon.running()) << daemon.log();
    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = readFile(dir / "cert.pem");
    // By address (no name lookup), checking the certificate against the name it was made for.
    grpc::ChannelArguments args;
    args.SetSslTargetNameOverride("localhost");
    auto channel = grpc::CreateCustomChannel(daemon.address(), grpc::SslCredentials(ssl), args);
    auto stub = pb::Partita::NewStub(channel);
    pb::ServerInfo info;
    auto ctx = context(10s, "tls-token");
    grpc::Status s = stub->GetServerInfo(ctx.get(), {}, &info);
    EXPECT_TRUE(s.ok()) << s.error_message();
    ctx = context(10s);
    EXPECT_EQ(stub->GetServerInfo(ctx.get(), {}, &info).error_code(), Code::UNAUTHENTICATED);
    // A plaintext client cannot talk to it.
    ctx = context(3s, "tls-token");
    EXPECT_FALSE(daemon.stub()->GetServerInfo(ctx.get(), {}, &info).ok());
}

}  // namespace
}  // namespace partita::test
