#include "daemon/flags.h"

#include <gtest/gtest.h>

#include <map>

namespace farm {
namespace {

struct FakeEnv {
  std::map<std::string, std::string> vars;
  const char* operator()(const char* name) const {
    const auto it = vars.find(name);
    return it == vars.end() ? nullptr : it->second.c_str();
  }
};

ParsedFlags Parse(std::vector<std::string> args, FakeEnv env = {{{"HOME", "/home/u"}}}) {
  return ParseWorkerFlags(args, env);
}

TEST(WorkerFlags, AllFlagsInBothForms) {
  const ParsedFlags f = Parse({"--coordinator", "farm.example:50051", "--cache-dir=/tmp/c",
                               "--threads", "3", "--name=render-07", "--texture-cache-mib", "64"});
  ASSERT_EQ(f.error, "");
  EXPECT_FALSE(f.help);
  EXPECT_EQ(f.options.coordinators, std::vector<std::string>{"farm.example:50051"});
  EXPECT_EQ(f.options.cache_dir, "/tmp/c");
  EXPECT_EQ(f.options.threads, 3);
  EXPECT_EQ(f.options.name, "render-07");
  EXPECT_EQ(f.options.texture_cache_mib, 64);
}

TEST(WorkerFlags, Defaults) {
  ParsedFlags f = Parse({"--coordinator=localhost:50051"});
  ASSERT_EQ(f.error, "");
  EXPECT_EQ(f.options.cache_dir, "/home/u/.cache/photonfarm/worker");
  EXPECT_EQ(f.options.threads, 0);
  EXPECT_EQ(f.options.name, "");
  EXPECT_EQ(f.options.cache_max_bytes, kDefaultCacheMaxBytes);
  EXPECT_EQ(f.options.texture_cache_mib, 512);
  f = Parse({"--coordinator=localhost:50051"}, {{{"HOME", "/home/u"}, {"XDG_CACHE_HOME", "/xdg"}}});
  EXPECT_EQ(f.options.cache_dir, "/xdg/photonfarm/worker");
  f = Parse({"--coordinator=localhost:50051"}, {{{"HOME", "/home/u"}, {"XDG_CACHE_HOME", "rel"}}});
  EXPECT_EQ(f.options.cache_dir, "/home/u/.cache/photonfarm/worker");
  f = Parse({"--coordinator=localhost:50051"}, FakeEnv{});
  EXPECT_NE(f.error.find("--cache-dir"), std::string::npos) << f.error;
}

TEST(WorkerFlags, ByteCountsTakeBinarySuffixes) {
  for (const auto& [value, want] : std::vector<std::pair<std::string, std::uint64_t>>{
           {"1", 1}, {"4096", 4096}, {"3K", 3 << 10}, {"64M", 64 << 20}, {"8G", std::uint64_t{8} << 30},
           {"2T", std::uint64_t{2} << 40}}) {
    ParsedFlags f = Parse({"--coordinator=h:1", "--cache-max-bytes", value});
    EXPECT_EQ(f.error, "") << value;
    EXPECT_EQ(f.options.cache_max_bytes, want) << value;
    f = Parse({"--coordinator=h:1", "--download-range-bytes=" + value});
    EXPECT_EQ(f.error, "") << value;
    EXPECT_EQ(f.options.download_range_bytes, want) << value;
  }
  EXPECT_EQ(Parse({"--coordinator=h:1"}).options.download_range_bytes, kDefaultDownloadRangeBytes);
}

TEST(WorkerFlags, Help) {
  EXPECT_TRUE(Parse({"--help"}).help);
  EXPECT_TRUE(Parse({"--coordinator=h:1", "-h"}).help);
  EXPECT_TRUE(Parse({"--help"}, FakeEnv{}).help);  // Help needs no cache directory.
}

TEST(WorkerFlags, AcceptsHostPortForms) {
  for (const char* ok : {"localhost:1", "10.0.0.7:50051", "[::1]:50051", "a-b.c:65535"}) {
    EXPECT_EQ(Parse({"--coordinator", ok}).error, "") << ok;
  }
}

TEST(WorkerFlags, ClearErrors) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{}, "--coordinator HOST:PORT is required"},
      {{"--coordinator"}, "--coordinator needs a value"},
      {{"--coordinator", "localhost"}, "is not HOST:PORT"},
      {{"--coordinator", "localhost:0"}, "is not HOST:PORT"},
      {{"--coordinator", "localhost:99999"}, "is not HOST:PORT"},
      {{"--coordinator", ":50051"}, "is not HOST:PORT"},
      {{"--coordinator", "::1:50051"}, "is not HOST:PORT"},
      {{"--coordinator=h:1", "--threads", "0"}, "--threads \"0\""},
      {{"--coordinator=h:1", "--threads", "2x"}, "--threads \"2x\""},
      {{"--coordinator=h:1", "--threads=-1"}, "--threads \"-1\""},
      {{"--coordinator=h:1", "--name="}, "--name is empty"},
      {{"--coordinator=h:1", "--texture-cache-mib=0"}, "--texture-cache-mib \"0\" is not a whole number from 1"},
      {{"--coordinator=h:1", "--texture-cache-mib", "lots"}, "--texture-cache-mib \"lots\""},
      {{"--coordinator=h:1", "--cache-dir="}, "--cache-dir is empty"},
      {{"--coordinator=h:1", "--cache-max-bytes=0"}, "--cache-max-bytes \"0\" is not a positive byte count"},
      {{"--coordinator=h:1", "--cache-max-bytes=8GB"}, "--cache-max-bytes \"8GB\""},
      {{"--coordinator=h:1", "--cache-max-bytes=G"}, "--cache-max-bytes \"G\""},
      {{"--coordinator=h:1", "--cache-max-bytes=99999999T"}, "--cache-max-bytes \"99999999T\""},
      {{"--coordinator=h:1", "--download-range-bytes=0"}, "--download-range-bytes \"0\" is not a positive byte count (e.g. 64M)"},
      {{"--coordinator=h:1", "--verbose"}, "unknown flag --verbose"},
      {{"--coordinator=h:1", "stray"}, "unexpected argument \"stray\""},
      {{"--coordinator=h:1", "--token="}, "--token is empty"},
      {{"--coordinator=h:1", "--tls-ca="}, "--tls-ca is empty"},
      {{"--coordinator=localhost:1", "--token", "a b"}, "printable ASCII"},
      {{"--coordinator=farm.example:1", "--token", "t"}, "refusing to send the worker token"},
      {{"--coordinator=127.0.0.1:1,10.0.0.2:1", "--token", "t"}, "to 127.0.0.1:1,10.0.0.2:1 (not loopback)"},
      {{"--coordinator", "a.example:1,b.example:1"}, "--coordinator: several addresses must be IP literals"},
  };
  for (const auto& [args, want] : cases) {
    const ParsedFlags f = Parse(args);
    EXPECT_NE(f.error.find(want), std::string::npos) << "got \"" << f.error << "\", want \"" << want << "\"";
  }
}

TEST(WorkerFlags, ATokenGoesInPlaintextOnlyWhenEveryReplicaIsOnLoopback) {
  const ParsedFlags f = Parse({"--coordinator=127.0.0.1:7001,127.0.0.1:7002", "--token=t"});
  ASSERT_EQ(f.error, "");
  EXPECT_EQ(f.options.coordinators, (std::vector<std::string>{"127.0.0.1:7001", "127.0.0.1:7002"}));
  EXPECT_EQ(JoinedAddresses(f.options), "127.0.0.1:7001,127.0.0.1:7002");
}

TEST(WorkerFlags, TokenFromFlagElseEnvironment) {
  FakeEnv env{{{"HOME", "/home/u"}, {"FARM_WORKER_TOKEN", "from-env"}}};
  EXPECT_EQ(Parse({"--coordinator=localhost:1"}, env).options.token, "from-env");
  EXPECT_EQ(Parse({"--coordinator=localhost:1", "--token=flag"}, env).options.token, "flag");
  EXPECT_EQ(Parse({"--coordinator=localhost:1"}).options.token, "");
}

TEST(WorkerFlags, TokenLeavesLoopbackOnlyWithTlsOrInsecure) {
  for (const char* local : {"localhost:1", "127.0.0.1:7070", "[::1]:7070"}) {
    EXPECT_EQ(Parse({"--coordinator", local, "--token", "t"}).error, "") << local;
  }
  ParsedFlags f = Parse({"--coordinator=farm.example:1", "--token=t", "--tls-ca", "/etc/ca.pem"});
  EXPECT_EQ(f.error, "");
  EXPECT_EQ(f.options.tls_ca, "/etc/ca.pem");
  f = Parse({"--coordinator=farm.example:1", "--token=t", "--insecure"});
  EXPECT_EQ(f.error, "");
  EXPECT_TRUE(f.options.insecure);
}

}  // namespace
}  // namespace farm
