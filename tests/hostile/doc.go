// Package hostile sends a real coordinator (in process, over real gRPC on loopback) well
// over a hundred malformed or hostile requests: broken scenes, bad RPC fields, forged
// lease reports, bad uploads. Each must get the right gRPC status with a message naming
// what is wrong, the coordinator must stay up, and no stored job or task may change.
package hostile
