// Command farm is the render farm's command-line tool: it runs a coordinator, submits
// scenes, follows and fetches jobs, and renders a scene on a local all-in-one farm.
// main only wires the verbs; each verb lives in a file of its own.
package main

import (
	"context"
	"os"
	"os/signal"
	"syscall"
)

func main() {
	ctx, stop := signal.NotifyContext(context.Background(), os.Interrupt, syscall.SIGTERM)
	code := run(ctx, os.Args[1:], &env{stdout: os.Stdout, stderr: os.Stderr, getenv: os.Getenv})
	stop()
	os.Exit(code)
}
