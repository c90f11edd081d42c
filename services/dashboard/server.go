// Package dashboard is the farm's web dashboard server: an http.Handler that serves the
// front end (web/dist, embedded) and the JSON and server-sent-events API of API.md,
// which it answers by calling the coordinator over gRPC.
//
// The dashboard holds no credential of its own: the browser's coordinator client token
// (the farm_token cookie, or an Authorization: Bearer header) is forwarded on every gRPC
// call as "authorization: Bearer TOKEN", so the coordinator decides what each request
// may do, and the gRPC connection itself carries no token.
package dashboard

import (
	"cmp"
	"embed"
	"io/fs"
	"log/slog"
	"net/http"
	"time"

	"google.golang.org/grpc"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// Defaults of Config's intervals and limits (API.md).
const (
	DefaultJobsPoll       = 500 * time.Millisecond
	DefaultWorkersEvery   = 2 * time.Second
	DefaultPingEvery      = 15 * time.Second
	DefaultJobUpdateEvery = 100 * time.Millisecond
	DefaultMaxStreams     = 100
	// callTimeout bounds each unary call to the coordinator.
	callTimeout = 60 * time.Second
)

// DialOptions are what a connection to the coordinator needs for the dashboard besides
// its transport credentials: message limits as large as the coordinator's (a job's
// 10,000 tasks, a scene with large inline meshes). Give the connection no per-RPC
// credentials: each call carries its request's token.
func DialOptions() []grpc.DialOption { return []grpc.DialOption{client.CallLimits()} }

//go:embed web/dist
var webFiles embed.FS

// Config wires a Server.
type Config struct {
	// Conn is the connection to the coordinator, without per-RPC credentials (the
	// browser's token is attached per call). Required.
	Conn grpc.ClientConnInterface
	// Logger defaults to slog.Default().
	Logger *slog.Logger
	// JobsPoll is how often the job list is read for the /api/events streams of a token
	// (at most one jobs-changed event per poll); WorkersEvery how often a stream sends
	// the workers; PingEvery how often an idle
	// stream gets a comment; JobUpdateEvery the least time between two updates of
	// /api/jobs/{id}/events. Zero means the default.
	JobsPoll, WorkersEvery, PingEvery, JobUpdateEvery time.Duration
	// MaxStreams bounds the event streams open at once (0: DefaultMaxStreams); more get
	// 503.
	MaxStreams int
	// RefusedTokenBurst is how many refused tokens a client address may present before
	// it is throttled (0: DefaultRefusedTokenBurst; throttle.go).
	RefusedTokenBurst int
	// Static serves the front end; nil serves the embedded web/dist.
	Static fs.FS
}

// Server is the dashboard's http.Handler.
type Server struct {
	cfg      Config
	log      *slog.Logger
	jobs     pb.JobServiceClient
	blobs    pb.BlobServiceClient
	files    *client.Client // uploads the files a browser sends with a scene
	mux      *http.ServeMux
	streams  chan struct{} // a slot per open event stream
	refused  *throttle     // refused tokens per client address
	jobFeeds *jobFeeds     // the job list, polled once per token for every /api/events stream
}

var _ http.Handler = (*Server)(nil)

// New returns the dashboard handler for the coordinator behind cfg.Conn.
func New(cfg Config) *Server {
	if cfg.Logger == nil {
		cfg.Logger = slog.Default()
	}
	// A period or a count that is not positive takes its default.
	cfg.JobsPoll = cmp.Or(max(cfg.JobsPoll, 0), DefaultJobsPoll)
	cfg.WorkersEvery = cmp.Or(max(cfg.WorkersEvery, 0), DefaultWorkersEvery)
	cfg.PingEvery = cmp.Or(max(cfg.PingEvery, 0), DefaultPingEvery)
	cfg.JobUpdateEvery = cmp.Or(max(cfg.JobUpdateEvery, 0), DefaultJobUpdateEvery)
	cfg.MaxStreams = cmp.Or(max(cfg.MaxStreams, 0), DefaultMaxStreams)
	cfg.RefusedTokenBurst = cmp.Or(max(cfg.RefusedTokenBurst, 0), DefaultRefusedTokenBurst)
	if cfg.Static == nil {
		sub, err := fs.Sub(webFiles, "web/dist")
		if err != nil {
			panic(err) // the embedded tree always has web/dist
		}
		cfg.Static = sub
	}
	s := &Server{
		cfg:     cfg,
		log:     cfg.Logger,
		jobs:    pb.NewJobServiceClient(cfg.Conn),
		blobs:   pb.NewBlobServiceClient(cfg.Conn),
		files:   client.New(cfg.Conn),
		mux:     http.NewServeMux(),
		streams: make(chan struct{}, cfg.MaxStreams),
		refused: newThrottle(cfg.RefusedTokenBurst, time.Now),
	}
	s.jobFeeds = newJobFeeds(s)
	s.routes()
	return s
}

func (s *Server) routes() {
	m := s.mux
	m.HandleFunc("POST /api/login", s.jsonPost(MaxSmallBody, s.login))
	m.HandleFunc("POST /api/logout", s.jsonPost(MaxSmallBody, s.logout))
	m.HandleFunc("GET /api/session", s.session)

	m.HandleFunc("GET /api/jobs", s.listJobs)
	m.HandleFunc("GET /api/jobs/{id}", s.getJob)
	m.HandleFunc("GET /api/jobs/{id}/tasks", s.listTasks)
	m.HandleFunc("GET /api/workers", s.listWorkers)
	m.HandleFunc("GET /api/blobs/{digest}", s.blob)

	m.HandleFunc("GET /api/events", s.farmEvents)
	m.HandleFunc("GET /api/jobs/{id}/events", s.jobEvents)

	m.HandleFunc("POST /api/jobs", s.jsonPost(MaxSceneBody, s.signedIn(s.submit)))
	m.HandleFunc("POST /api/jobs/{id}/cancel", s.jsonPost(MaxSmallBody, s.cancel))
	m.HandleFunc("POST /api/jobs/{id}/priority", s.jsonPost(MaxSmallBody, s.setPriority))
	m.HandleFunc("POST /api/jobs/{id}/unblock", s.jsonPost(MaxSmallBody, s.unblock))
	m.HandleFunc("POST /api/jobs/{id}/requeue", s.jsonPost(MaxSmallBody, s.requeue))
	m.HandleFunc("POST /api/jobs/{id}/tasks/{task}/retry", s.jsonPost(MaxSmallBody, s.retry))
	m.HandleFunc("POST /api/jobs/{id}/delete", s.jsonPost(MaxSmallBody, s.deleteJob))

	// Anything else under /api/ is a JSON 404 (or 405), never the front end's page.
	m.HandleFunc("/api/", func(w http.ResponseWriter, r *http.Request) {
		writeJSON(w, http.StatusNotFound, map[string]any{"error": "no such API endpoint: " + r.Method + " " + r.URL.Path})
	})
	static := http.FileServerFS(s.cfg.Static)
	m.Handle("/", http.HandlerFunc(func(w http.ResponseWriter, r *http.Request) {
		if r.Method != http.MethodGet && r.Method != http.MethodHead {
			w.Header().Set("Allow", "GET, HEAD")
			http.Error(w, "method not allowed", http.StatusMethodNotAllowed)
			return
		}
		// The front end changes with the build; the browser asks again each time (and
		// gets 304 when it has not changed).
		w.Header().Set("Cache-Control", "no-cache")
		static.ServeHTTP(w, r)
	}))
}

// ServeHTTP sets the security headers every answer carries, refuses cross-origin
// state changes and the tokens of a client address that has had too many refused, and
// routes the request. Bodies are read (within their endpoint's limit) by the handlers
// that need them.
func (s *Server) ServeHTTP(w http.ResponseWriter, r *http.Request) {
	h := w.Header()
	h.Set("Content-Security-Policy", "default-src 'self'")
	h.Set("X-Content-Type-Options", "nosniff")
	h.Set("X-Frame-Options", "DENY")
	h.Set("Referrer-Policy", "same-origin")
	if err := crossOrigin.Check(r); err != nil {
		s.writeError(w, r, errorf(http.StatusForbidden, "refused a cross-origin request: the dashboard takes actions only from its own pages"))
		return
	}
	if presentsToken(r) && !s.refused.allowed(clientKey(r)) {
		s.throttled(w, r)
		return
	}
	s.mux.ServeHTTP(w, r)
}
