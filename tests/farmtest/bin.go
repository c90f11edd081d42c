// Package farmtest runs a real photon farm for tests: `farm coordinator` and `farm-worker`
// processes from $FARM_BIN_DIR, each in a process group of its own with its output in a log
// file, a client connected to the coordinator, and helpers to submit scenes, wait for jobs,
// download their outputs and run the `farm` CLI. Everything a test starts is killed in its
// t.Cleanup, and the last lines of every log are printed when the test has failed.
//
// tests/integration, tests/stiff and tests/fault share it so that the rules of running the
// binaries (fail, never skip, without them; process groups; reading the coordinator's
// port from its log) live in one place.
package farmtest

import (
	"os"
	"path/filepath"
	"runtime"
	"testing"
)

// BinDir returns $FARM_BIN_DIR, where `farm` and `farm-worker` are built, as an absolute
// path. The tests exist to run the real binaries: without them they fail rather than
// skip, because a skipped assertion looks like a pass.
func BinDir(t testing.TB) string {
	t.Helper()
	dir := os.Getenv("FARM_BIN_DIR")
	if dir == "" {
		t.Fatal("FARM_BIN_DIR is not set: these tests run the built binaries. Build them " +
			"(make build) and run FARM_BIN_DIR=$PWD/build/bin go test ./tests/..., or run make test")
	}
	for _, b := range []string{"farm", "farm-worker"} {
		if _, err := os.Stat(filepath.Join(dir, b)); err != nil {
			t.Fatalf("FARM_BIN_DIR=%s: %v (build with make build)", dir, err)
		}
	}
	abs, err := filepath.Abs(dir)
	if err != nil {
		t.Fatal(err)
	}
	return abs
}

// RepoRoot is the module root, two folders above this package.
func RepoRoot() string {
	_, file, _, _ := runtime.Caller(0)
	return filepath.Dir(filepath.Dir(filepath.Dir(file)))
}
