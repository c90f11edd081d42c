#pragma once

// The coordinator addresses a farm-worker is given (--coordinator), and the gRPC target
// that reaches them. Coordinator replicas share their state in Redis, so any of them may
// serve any call: a worker spreads its calls over every replica it can reach (gRPC's
// round_robin policy) and carries on with the others when one goes away.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace farm {

// Splits "HOST:PORT[,HOST:PORT...]" into its addresses. One address may be a DNS name
// (gRPC then uses every address the name resolves to, as a Kubernetes Service or a
// compose network alias gives); several must be IP literals of one family (10.0.0.1:50051
// or [fd00::1]:50051), because gRPC's list targets (ipv4:, ipv6:) take no names.
// Returns the error in one line, or nullopt with the addresses in out.
std::optional<std::string> ParseCoordinatorAddresses(std::string_view text, std::vector<std::string>& out);

// The gRPC target for addresses from ParseCoordinatorAddresses: the address itself for
// one, "ipv4:A,B" or "ipv6:A,B" for several.
std::string CoordinatorTarget(const std::vector<std::string>& addresses);

// Whether HOST:PORT names this machine without leaving it (localhost, 127.x.y.z, [::1]).
// Names are not resolved.
bool IsLoopbackAddress(std::string_view host_port);

}  // namespace farm
