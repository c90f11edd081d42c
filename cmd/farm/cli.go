package main

import (
	"context"
	"errors"
	"flag"
	"fmt"
	"io"
	"os"
	"strings"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/client"
	"photonfarm/contract/suggest"
)

// Exit codes.
const (
	exitOK          = 0
	exitFailure     = 1   // the farm failed, the job failed, the coordinator is unreachable
	exitUsage       = 2   // bad command line or invalid input (a malformed scene)
	exitInterrupted = 130 // Ctrl-C
)

// env is what a verb may touch of the process, so that tests can run verbs in-process.
type env struct {
	stdout, stderr io.Writer
	getenv         func(string) string
}

// A verb is one subcommand: `farm NAME ARGS...`.
type verb struct {
	name    string
	args    string // synopsis after the name
	summary string
	run     func(ctx context.Context, e *env, args []string) error
}

// verbs in the order `farm help` lists them.
var verbs []*verb

func init() {
	verbs = []*verb{
		renderVerb, importVerb, coordinatorVerb, dashboardVerb, submitVerb, watchVerb, fetchVerb,
		statusVerb, listVerb, tasksVerb, cancelVerb, requeueVerb, retryVerb, deleteVerb, priorityVerb, unblockVerb, validateVerb, planVerb, reportVerb,
		versionVerb,
	}
}

const usageHeader = `farm is the photon-mapping render farm's command-line tool.

usage: farm VERB [ARGS] [FLAGS]    (flags may come before or after the arguments)

verbs:
`

const usageFooter = `
Client verbs talk to the coordinator at --coordinator, else $FARM_COORDINATOR, else
localhost:7070, with the client token --token, else $FARM_TOKEN, over TLS if --tls-ca
(else $FARM_TLS_CA) names the CA to trust; a token goes in plaintext only to loopback
unless --insecure. Exit status: 0 success; 1 failure (job failed, coordinator unreachable);
2 bad usage or invalid input (the message names the scene field); 130 interrupted.
Run 'farm VERB -h' for a verb's flags.
`

func printUsage(w io.Writer) {
	fmt.Fprint(w, usageHeader)
	for _, v := range verbs {
		synopsis, _, _ := strings.Cut(v.args, "[")
		fmt.Fprintf(w, "  %-30s %s\n", strings.TrimSpace(v.name+" "+synopsis), v.summary)
	}
	fmt.Fprintf(w, "  %-30s %s\n", "help [VERB]", "show this help, or a verb's")
	fmt.Fprint(w, usageFooter)
}

// verbHint is ` (did you mean "render"?)` for a misspelled verb, "" for one too far
// from any.
func verbHint(name string) string {
	names := []string{"help"}
	for _, v := range verbs {
		names = append(names, v.name)
	}
	return suggest.Hint(name, names)
}

func findVerb(name string) *verb {
	for _, v := range verbs {
		if v.name == name {
			return v
		}
	}
	return nil
}

// run executes the command line args (without the program name) and returns the exit code.
func run(ctx context.Context, args []string, e *env) int {
	if len(args) == 0 {
		printUsage(e.stderr)
		return exitUsage
	}
	name, rest := args[0], args[1:]
	switch name {
	case "help", "-h", "-help", "--help":
		if len(rest) > 0 {
			if v := findVerb(rest[0]); v != nil {
				return run(ctx, []string{v.name, "-h"}, e)
			}
			fmt.Fprintf(e.stderr, "farm: unknown verb %q%s (see 'farm help')\n", rest[0], verbHint(rest[0]))
			return exitUsage
		}
		printUsage(e.stdout)
		return exitOK
	case "-version", "--version":
		name = versionVerb.name
	}
	v := findVerb(name)
	if v == nil {
		fmt.Fprintf(e.stderr, "farm: unknown verb %q%s (see 'farm help')\n", name, verbHint(name))
		return exitUsage
	}
	err := v.run(ctx, e, rest)
	if err == nil {
		return exitOK
	}
	if errors.Is(err, flag.ErrHelp) {
		return exitOK
	}
	var ex *exitError
	if errors.As(err, &ex) && ex.silent {
		return ex.code
	}
	code := exitCode(ctx, err)
	msg := oneLine(err.Error()) + hint(err)
	if code == exitInterrupted && errors.Is(err, context.Canceled) {
		msg = "interrupted"
	}
	fmt.Fprintf(e.stderr, "farm: %s\n", msg)
	return code
}

func exitCode(ctx context.Context, err error) int {
	var ex *exitError
	switch {
	case errors.As(err, &ex):
		return ex.code
	case errors.Is(err, context.Canceled) && ctx.Err() != nil:
		return exitInterrupted
	case client.IsInvalidInput(err):
		return exitUsage
	}
	return exitFailure
}

// exitError carries an exit code; silent ones have been reported already.
type exitError struct {
	code   int
	err    error
	silent bool
}

func (e *exitError) Error() string { return e.err.Error() }
func (e *exitError) Unwrap() error { return e.err }

func usageErrorf(format string, args ...any) error {
	return &exitError{code: exitUsage, err: fmt.Errorf(format, args...)}
}

// flagSet is a verb's flags and how to print its usage.
type flagSet struct {
	*flag.FlagSet
	usage func()
}

// newFlags returns the flags of the verb named name; its -h prints the verb's usage on
// stdout.
func newFlags(name string, e *env) *flagSet {
	v := findVerb(name)
	fs := &flagSet{FlagSet: flag.NewFlagSet("farm "+v.name, flag.ContinueOnError)}
	fs.SetOutput(io.Discard)
	fs.FlagSet.Usage = func() {} // the flag package calls it on errors too; parse decides
	fs.usage = func() {
		w := e.stdout
		fmt.Fprintf(w, "usage: farm %s %s\n\n%s\n", v.name, v.args, v.summary)
		if doc := verbDocs[v.name]; doc != "" {
			fmt.Fprintf(w, "\n%s", doc)
		}
		hasFlags := false
		fs.VisitAll(func(*flag.Flag) { hasFlags = true })
		if hasFlags {
			fmt.Fprintln(w, "\nflags:")
			fs.SetOutput(w)
			fs.PrintDefaults()
			fs.SetOutput(io.Discard)
		}
	}
	return fs
}

// parse parses flags and positional arguments in any order and checks that there are
// between minArgs and maxArgs positional arguments (maxArgs < 0: no limit).
func parse(fs *flagSet, args []string, minArgs, maxArgs int) ([]string, error) {
	var pos []string
	for {
		if err := fs.Parse(args); err != nil {
			if errors.Is(err, flag.ErrHelp) {
				fs.usage()
				return nil, err
			}
			return nil, usageErrorf("%s: %v%s (see '%s -h')", strings.TrimPrefix(fs.Name(), "farm "), err, flagHint(fs, err), fs.Name())
		}
		args = fs.Args()
		if len(args) == 0 {
			break
		}
		pos = append(pos, args[0])
		args = args[1:]
	}
	if len(pos) < minArgs || (maxArgs >= 0 && len(pos) > maxArgs) {
		return nil, usageErrorf("%s: wrong number of arguments (see '%s -h')", strings.TrimPrefix(fs.Name(), "farm "), fs.Name())
	}
	return pos, nil
}

// undefinedFlag is how the flag package begins the error for a flag fs does not define.
const undefinedFlag = "flag provided but not defined: -"

// flagHint is ` (did you mean --workers?)` when err is about an undefined flag near one
// that fs defines.
func flagHint(fs *flagSet, err error) string {
	name, ok := strings.CutPrefix(err.Error(), undefinedFlag)
	if !ok {
		return ""
	}
	var names []string
	fs.VisitAll(func(f *flag.Flag) { names = append(names, f.Name) })
	if c, ok := suggest.Closest(strings.TrimLeft(name, "-"), names); ok {
		return " (did you mean --" + c + "?)"
	}
	return ""
}

// coordinatorFlag adds --coordinator to fs; the returned func gives the address to use.
func coordinatorFlag(fs *flagSet, e *env) func() string {
	addr := fs.String("coordinator", "", "coordinator address HOST:PORT, or replicas HOST:PORT,HOST:PORT (default $FARM_COORDINATOR, else "+client.DefaultAddress+")")
	return func() string {
		if *addr != "" {
			return *addr
		}
		if a := e.getenv("FARM_COORDINATOR"); a != "" {
			return a
		}
		return client.DefaultAddress
	}
}

// assetRootFlag adds --asset-root to fs: the folder the files a scene names must lie in
// (empty: the scene file's folder).
func assetRootFlag(fs *flagSet) *string {
	return fs.String("asset-root", "", "`folder` every mesh and reference file the scene names must lie in, symbolic links resolved (default: the scene file's folder)")
}

// connFlags are the flags of client verbs that say how to reach the coordinator.
type connFlags struct {
	addr     func() string
	token    *string
	tlsCA    *string
	insecure *bool
	e        *env
}

// addConnFlags adds --coordinator, --token, --tls-ca and --insecure to fs.
func addConnFlags(fs *flagSet, e *env) *connFlags {
	return &connFlags{
		addr:     coordinatorFlag(fs, e),
		token:    fs.String("token", "", "client `token` sent with every call (default $FARM_TOKEN; prefer the variable, a command line is visible to other users)"),
		tlsCA:    fs.String("tls-ca", "", "connect with TLS, trusting the CA certificates in this PEM `file` (default $FARM_TLS_CA; none: plaintext)"),
		insecure: fs.Bool("insecure", false, "allow sending the token without TLS to a coordinator that is not on loopback"),
		e:        e,
	}
}

// dial connects to the coordinator the flags name. A token is sent without TLS only to a
// loopback address, unless --insecure.
func (cf *connFlags) dial() (*client.Client, error) {
	addr := cf.addr()
	token := *cf.token
	if token == "" {
		token = cf.e.getenv("FARM_TOKEN")
	}
	ca := *cf.tlsCA
	if ca == "" {
		ca = cf.e.getenv("FARM_TLS_CA")
	}
	opts := []client.Option{client.WithToken(token)}
	if ca != "" {
		opts = append(opts, client.WithTLS(ca))
	}
	if *cf.insecure {
		opts = append(opts, client.AllowPlaintextToken())
	}
	c, err := client.Dial(addr, opts...)
	if errors.Is(err, client.ErrPlaintextToken) {
		return nil, usageErrorf("refusing to send the token without TLS to %s, which is not loopback: pass --tls-ca FILE, or --insecure on a trusted network", addr)
	}
	return c, err
}

// withClient is how a client verb runs once it has declared its own flags on fs: it adds
// the connection flags (--coordinator, --token, --tls-ca, --insecure), parses args (see
// parse), dials the coordinator and runs call with the client and the positional
// arguments, closing the client after.
func withClient(fs *flagSet, e *env, args []string, minArgs, maxArgs int, call func(c *client.Client, pos []string) error) error {
	cf := addConnFlags(fs, e)
	pos, err := parse(fs, args, minArgs, maxArgs)
	if err != nil {
		return err
	}
	c, err := cf.dial()
	if err != nil {
		return err
	}
	defer c.Close()
	return call(c, pos)
}

// hint says what to do about an unreachable coordinator or a missing, unknown or
// wrong-role token, for the error line.
func hint(err error) string {
	switch status.Code(err) {
	case codes.Unavailable:
		return " (is a coordinator running there? start one with 'farm coordinator', or name it with --coordinator HOST:PORT or $FARM_COORDINATOR; 'farm render' runs a local farm)"
	case codes.Unauthenticated:
		return " (give a client token with --token or $FARM_TOKEN)"
	case codes.PermissionDenied:
		return " (farm's verbs need one of the coordinator's client tokens, from its --client-token-file or $FARM_CLIENT_TOKENS, in --token or $FARM_TOKEN)"
	}
	return ""
}

// isTerminal reports whether w is a character device (a terminal).
func isTerminal(w io.Writer) bool {
	f, ok := w.(*os.File)
	if !ok {
		return false
	}
	fi, err := f.Stat()
	return err == nil && fi.Mode()&os.ModeCharDevice != 0
}

// verbDocs holds the longer help of verbs that need it.
var verbDocs = map[string]string{
	"render": `Runs a whole farm on this machine: an in-process coordinator on a free loopback port
with a temporary data folder, N farm-worker processes, then submits SCENE, shows
progress, and writes OUTDIR/NAME.exr and OUTDIR/NAME.png, NAME being --name, else the
scene's name field made file-safe, else the scene file's name without .json: the name
farm fetch gives the same job's files (farm submit names a nameless scene after its file
too). Workers are
stopped (SIGTERM) and the temporary folder removed at the end, on failure and on Ctrl-C.
farm-worker is found through --worker-bin, else next to the farm executable, else $PATH.
The local farm is authenticated: farm makes random client and worker tokens and gives
the worker token to its workers. It also serves the web dashboard of the local farm
(--dashboard-listen, default a free loopback port; --no-dashboard to skip) and prints
"dashboard on http://127.0.0.1:PORT/" and the run's client token to log in with before
the progress; both last only as long as the render. --exposure +1 renders the PNG
preview one stop brighter (it overrides the scene's output.exposure_stops; the EXR stays
linear: docs/output.md).
`,
	"dashboard": `Serves the web dashboard (the job list, a job's tiles as they finish, the workers;
submit, cancel, reprioritise) for the coordinator at --coordinator, and prints
"dashboard on http://HOST:PORT/" on stdout once it accepts connections. It holds no
token of its own: each browser logs in with a coordinator client token, kept in an
HttpOnly cookie and forwarded with every call. Over plain HTTP, so it listens on
loopback by default; forwarding tokens to a coordinator that is not on loopback needs
--tls-ca (or --insecure on a trusted network).
`,
	"coordinator": `Serves JobService, WorkerService and BlobService until SIGINT or SIGTERM, then stops
gracefully. Prints "coordinator listening on HOST:PORT" on stderr once it accepts
connections (with --listen 127.0.0.1:0 the port is chosen by the system).

Calls need a token (gRPC metadata "authorization: Bearer TOKEN"): a client token for
JobService, a worker token for WorkerService, either for BlobService. Tokens come from
--client-token-file and --worker-token-file and from $FARM_CLIENT_TOKENS and
$FARM_WORKER_TOKENS. With no token at all, authentication is OFF: anyone who can connect
may do anything (a loud warning if the address is not loopback). --tls-cert and
--tls-key serve TLS; without them tokens travel in plaintext.
`,
	"fetch": `Downloads the outputs of a succeeded job as DIR/NAME.exr (the final image) and
DIR/NAME.png (the preview), NAME being --name, else the job's display name (the scene's
name field, made file-safe; farm submit and farm render give a nameless scene its file's
name), else the job id: the names farm render gives the same job's files. Each download is checked against its
sha256 digest before it replaces a file.
`,
	"plan": `Reads SCENE (JSON), validates it and plans it here, with the coordinator's planner and
no coordinator, and prints one line per pass the renderer knows (run or skip, and why:
e.g. "skip caustic photon map: no specular surface"), then the tasks per phase of the
first round. Mesh and reference files are hashed and meshes checked (a broken OBJ is
refused with its file, line and reason), not uploaded.
`,
	"validate": `Reads each SCENE (JSON) and checks it as farm submit and the coordinator would: the
JSON against the contract (an unknown field or enum value is named with the file, the
line, the field path and the nearest declared name: "s.json: line 3:5: film.widht:
unknown field "widht" (did you mean "width"?)"), every rule on its fields, and the mesh
and reference files it names. Prints "SCENE: ok" per file; the first invalid one stops
it with exit status 2. No coordinator is needed.
`,
	"report": `Prints a job's progressive rounds as a table: seconds since the job was submitted,
photon paths and samples per pixel so far, the estimated error (from round 2 on; an
estimate the renderer makes without a reference) and the RMSE against the scene's reference image (if it names
one). With -o FILE.svg it also writes the error-against-time chart (log-log axes, one
marker per round and error kind).
`,
	"priority": `Sets the priority of a job that has not ended: among jobs with work to do, the
highest priority is leased first, and jobs of equal priority share the workers (the one
holding the fewest leases goes next). Leases granted already stand. N may be negative
("farm priority JOB -5").
`,
	"unblock": `A worker that fails 3 tasks of a job is blocked from it (farm status JOB lists the
blocked workers and why). unblock lets WORKER, or without it every blocked worker, lease
the job's tasks again, with its failure count reset.
`,
	"submit": `Reads SCENE (JSON), checks the mesh files it names (paths relative to the scene file)
and uploads them, submits it and prints the job id on stdout. --priority N (in [-1000,
1000], default 0) puts it ahead of (or behind) jobs of lower (higher) priority. A malformed
scene is refused before the network (validated as farm validate does: the file, then the
field at fault) with exit status 2, and so is a mesh that does not
parse (naming the file, the line and the reason), a path that is not a regular file, and
a file outside the asset root (--asset-root, by default the scene file's folder: no "..",
absolute path or symbolic link leading out). The submission carries a request id, so the
coordinator makes one job of it however often the call is retried.
`,
}
