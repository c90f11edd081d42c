#include "daemon/coordinator_address.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace farm {
namespace {

std::vector<std::string> Parsed(std::string_view text) {
  std::vector<std::string> out;
  const auto error = ParseCoordinatorAddresses(text, out);
  EXPECT_FALSE(error) << text << ": " << error.value_or("");
  return out;
}

TEST(CoordinatorAddress, OneAddressOfAnyFormIsItsOwnTarget) {
  for (const char* one : {"localhost:1", "coordinator:50051", "10.0.0.7:50051", "[::1]:50051", "a-b.c:65535"}) {
    const auto addresses = Parsed(one);
    ASSERT_EQ(addresses.size(), 1u) << one;
    // A name is resolved by gRPC's DNS resolver, to every address it has.
    EXPECT_EQ(CoordinatorTarget(addresses), one);
  }
}

TEST(CoordinatorAddress, SeveralLiteralsOfOneFamilyMakeAListTarget) {
  EXPECT_EQ(CoordinatorTarget(Parsed("127.0.0.1:7001,10.1.2.3:7002")), "ipv4:127.0.0.1:7001,10.1.2.3:7002");
  EXPECT_EQ(CoordinatorTarget(Parsed("[::1]:7001,[fd00::2]:7002")), "ipv6:[::1]:7001,[fd00::2]:7002");
}

TEST(CoordinatorAddress, RefusesWhatGrpcCannotReachWithTheReason) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "\"\" is not HOST:PORT"},
      {"localhost", "\"localhost\" is not HOST:PORT"},
      {"localhost:0", "is not HOST:PORT"},
      {"localhost:99999", "is not HOST:PORT"},
      {":50051", "is not HOST:PORT"},
      {"::1:50051", "is not HOST:PORT"},
      {"10.0.0.1:1,", "\"\" is not HOST:PORT"},
      {"10.0.0.1:1,,10.0.0.2:1", "\"\" is not HOST:PORT"},
      {"a.example:1,b.example:1", "several addresses must be IP literals"},
      {"10.0.0.1:1,b.example:1", "all IPv4 or all IPv6"},
      {"10.0.0.1:1,[::1]:1", "all IPv4 or all IPv6"},
      {"10.0.0.1:1,10.0.0.1:1", "\"10.0.0.1:1\" is listed twice"},
      {"[zz]:1,[::1]:1", "all IPv4 or all IPv6"},  // [zz] is no IPv6 literal, so a name
  };
  for (const auto& [text, want] : cases) {
    std::vector<std::string> out;
    const auto error = ParseCoordinatorAddresses(text, out);
    ASSERT_TRUE(error) << text;
    EXPECT_NE(error->find(want), std::string::npos) << text << ": got \"" << *error << "\", want \"" << want << "\"";
  }
}

TEST(CoordinatorAddress, LoopbackIsJudgedByTheHostOnly) {
  for (const char* yes : {"localhost:1", "127.0.0.1:50051", "127.9.9.9:1", "[::1]:1"}) EXPECT_TRUE(IsLoopbackAddress(yes)) << yes;
  for (const char* no : {"10.0.0.1:1", "local:1", "[::2]:1", "128.0.0.1:1"}) EXPECT_FALSE(IsLoopbackAddress(no)) << no;
}

}  // namespace
}  // namespace farm
