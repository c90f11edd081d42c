package redistest

import (
	"context"
	"fmt"
	"strconv"
	"strings"
	"sync"
	"time"

	"github.com/redis/go-redis/v9"
)

// A CPUMeter times each command of one client by the CPU time Redis's main thread spent
// while it ran (INFO cpu before and after it). Unlike the slow log's clock, CPU time does
// not grow while Redis waits for a core on a loaded machine, so a bound on it holds on a
// shared machine as well as on an idle one. It is exact only while the metered client is
// the only one Redis serves.
type CPUMeter struct {
	srv  *Server
	info *redis.Client

	mu    sync.Mutex
	worst time.Duration
	what  string
}

// MeteredClient returns a client of the server whose commands (not pipelines) are timed by
// the returned meter; both are closed in t.Cleanup.
func (s *Server) MeteredClient() (*redis.Client, *CPUMeter) {
	m := &CPUMeter{srv: s, info: s.Client()}
	c := s.Client()
	c.AddHook(m)
	return c, m
}

// Worst returns the command that took the most CPU since the last call, with the start of
// its arguments, and forgets it.
func (m *CPUMeter) Worst() (time.Duration, string) {
	m.mu.Lock()
	defer m.mu.Unlock()
	d, what := m.worst, m.what
	m.worst, m.what = 0, ""
	return d, what[:min(len(what), 60)]
}

// cpu is the CPU time Redis's main thread has used, user and system.
func (m *CPUMeter) cpu(ctx context.Context) time.Duration {
	info, err := m.info.Info(ctx, "cpu").Result()
	if err != nil {
		m.srv.t.Errorf("INFO cpu: %v", err)
		return 0
	}
	var total time.Duration
	for _, line := range strings.Split(info, "\n") {
		k, v, _ := strings.Cut(strings.TrimSpace(line), ":")
		if k == "used_cpu_user_main_thread" || k == "used_cpu_sys_main_thread" {
			sec, err := strconv.ParseFloat(v, 64)
			if err != nil {
				m.srv.t.Errorf("INFO cpu: %s: %v", line, err)
			}
			total += time.Duration(sec * float64(time.Second))
		}
	}
	return total
}

// DialHook implements redis.Hook.
func (m *CPUMeter) DialHook(next redis.DialHook) redis.DialHook { return next }

// ProcessPipelineHook implements redis.Hook: pipelines are not metered (Redis serves
// other clients between their commands).
func (m *CPUMeter) ProcessPipelineHook(next redis.ProcessPipelineHook) redis.ProcessPipelineHook {
	return next
}

// ProcessHook implements redis.Hook.
func (m *CPUMeter) ProcessHook(next redis.ProcessHook) redis.ProcessHook {
	return func(ctx context.Context, cmd redis.Cmder) error {
		before := m.cpu(ctx)
		err := next(ctx, cmd)
		used := m.cpu(ctx) - before
		m.mu.Lock()
		if used > m.worst {
			m.worst, m.what = used, fmt.Sprint(cmd.Args())
		}
		m.mu.Unlock()
		return err
	}
}
