// Package integration holds the farm's cross-component tests: a real coordinator process
// (`farm coordinator`), real farm-worker processes and the farm CLI, talking gRPC over
// loopback. The tests need built binaries in $FARM_BIN_DIR (the Makefile sets it to
// build/bin); see tests/README.md.
package integration
