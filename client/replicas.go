package client

import (
	"fmt"
	"net"
	"strings"

	"google.golang.org/grpc"
	"google.golang.org/grpc/resolver"
	"google.golang.org/grpc/resolver/manual"
)

// Coordinator replicas on one Redis serve the same jobs, so a client may be given all of
// them: "host:port,host:port". Its calls are spread over the replicas that answer (gRPC's
// round_robin) and go on through the others when one goes away. One DNS name that
// resolves to every replica (a Kubernetes Service, a compose network alias) fails over
// the same way, through gRPC's DNS resolver and pick_first, without the spreading.
// farm-worker and the Python SDK take the same forms, except that their lists must be IP
// literals (gRPC core's list targets take no names: worker/daemon/coordinator_address.h);
// Go resolves each name of a list itself.

// roundRobin is the service config that spreads calls over every address of the target.
const roundRobin = `{"loadBalancingConfig":[{"round_robin":{}}]}`

// replicasScheme names the resolver that lists the replicas given in a comma list.
const replicasScheme = "farm-replicas"

// addresses splits addr into the replicas' addresses, each "host:port" or a gRPC target
// of its own (dns:///host:port, unix:path) when addr names one.
func addresses(addr string) ([]string, error) {
	if addr == "" {
		return nil, fmt.Errorf("empty coordinator address")
	}
	if !strings.Contains(addr, ",") {
		return []string{addr}, nil
	}
	parts := strings.Split(addr, ",")
	seen := make(map[string]bool, len(parts))
	for _, p := range parts {
		if _, port, err := net.SplitHostPort(p); err != nil || port == "" {
			return nil, fmt.Errorf("coordinator address %q in the list %q is not host:port", p, addr)
		}
		if seen[p] {
			return nil, fmt.Errorf("coordinator address %q is listed twice in %q", p, addr)
		}
		seen[p] = true
	}
	return parts, nil
}

// ReplicaTarget is the gRPC target and the dial options that reach the replicas at addr
// (one address, or a comma list whose calls are spread over them).
func ReplicaTarget(addr string) (string, []grpc.DialOption, error) {
	addrs, err := addresses(addr)
	if err != nil {
		return "", nil, err
	}
	if len(addrs) == 1 {
		// gRPC's default, pick_first: calls go to the first address that answers and move
		// to the next when it goes. (round_robin here made the first call after a restarted
		// coordinator fail on the old connection, where pick_first reconnects.)
		return addr, nil, nil
	}
	// One authority for every connection, the first replica's: with TLS the replicas'
	// certificate must name it (gRPC checks each connection against the channel's).
	opts := []grpc.DialOption{grpc.WithDefaultServiceConfig(roundRobin), grpc.WithAuthority(addrs[0])}
	list := manual.NewBuilderWithScheme(replicasScheme)
	state := resolver.State{}
	for _, a := range addrs {
		state.Addresses = append(state.Addresses, resolver.Address{Addr: a})
	}
	list.InitialState(state)
	return replicasScheme + ":///" + addr, append(opts, grpc.WithResolvers(list)), nil
}
