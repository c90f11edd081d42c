package main

import (
	"bufio"
	"context"
	"errors"
	"fmt"
	"net"
	"os"
	"os/exec"
	"path/filepath"
	"strconv"
	"strings"
	"time"
)

// farm is a redis-server and coordinator processes on it, sharing one blob folder.
type farm struct {
	redis  *exec.Cmd
	coords []*exec.Cmd
	addrs  []string
}

func freePort() (int, error) {
	l, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		return 0, err
	}
	defer l.Close()
	return l.Addr().(*net.TCPAddr).Port, nil
}

// startFarm starts redis-server (no persistence: the simulation measures the
// coordinator, not the disk) and replicas coordinators on it.
func startFarm(ctx context.Context, bin, dir string, replicas int, profileDir string) (*farm, error) {
	port, err := freePort()
	if err != nil {
		return nil, err
	}
	f := &farm{redis: exec.CommandContext(ctx, "redis-server", "--port", strconv.Itoa(port), "--bind", "127.0.0.1",
		"--save", "", "--appendonly", "no", "--dir", dir)}
	if err := f.redis.Start(); err != nil {
		return nil, fmt.Errorf("start redis-server: %w", err)
	}
	redisURL := fmt.Sprintf("redis://127.0.0.1:%d/0", port)
	blobs := "file://" + filepath.Join(dir, "blobs")
	for i := range replicas {
		// The first coordinator creates the key layout; the others find it.
		var extra []string
		if profileDir != "" {
			extra = []string{"--cpu-profile", filepath.Join(profileDir, fmt.Sprintf("coordinator-%d.pprof", i))}
		}
		addr, cmd, err := startCoordinator(ctx, bin, filepath.Join(dir, fmt.Sprintf("coord-%d", i)), redisURL, blobs, extra...)
		if cmd != nil {
			f.coords = append(f.coords, cmd)
		}
		if err != nil {
			f.stop()
			return nil, err
		}
		f.addrs = append(f.addrs, addr)
	}
	return f, nil
}

func startCoordinator(ctx context.Context, bin, dataDir, redisURL, blobs string, extra ...string) (string, *exec.Cmd, error) {
	// Redis may still be starting: the coordinator checks it answers and exits if not,
	// so try a few times.
	for attempt := 0; ; attempt++ {
		args := append([]string{"coordinator", "--listen", "127.0.0.1:0", "--data-dir", dataDir, "--blobs", blobs,
			"--redis", redisURL, "--log-level", "warn", "--lease-duration", "30s"}, extra...)
		cmd := exec.CommandContext(ctx, filepath.Join(bin, "farm"), args...)
		stderr, err := cmd.StderrPipe()
		if err != nil {
			return "", nil, err
		}
		if err := cmd.Start(); err != nil {
			return "", nil, err
		}
		addrc := make(chan string, 1)
		go func() {
			sc := bufio.NewScanner(stderr)
			for sc.Scan() {
				if _, addr, ok := strings.Cut(sc.Text(), "coordinator listening on "); ok {
					addrc <- strings.TrimSpace(addr)
				} else {
					fmt.Fprintln(os.Stderr, "  coordinator:", sc.Text())
				}
			}
			close(addrc)
		}()
		select {
		case addr, ok := <-addrc:
			if ok {
				return addr, cmd, nil
			}
			_ = cmd.Wait()
			if attempt < 20 {
				time.Sleep(100 * time.Millisecond)
				continue
			}
			return "", nil, errors.New("the coordinator exited before listening")
		case <-time.After(20 * time.Second):
			return "", cmd, errors.New("the coordinator did not start listening within 20s")
		}
	}
}

// stop ends the coordinators with SIGINT and waits for them, then Redis, so that no
// coordinator stops with its Redis gone.
func (f *farm) stop() {
	for _, c := range f.coords {
		_ = c.Process.Signal(os.Interrupt)
	}
	for _, c := range f.coords {
		_ = c.Wait()
	}
	_ = f.redis.Process.Signal(os.Interrupt)
	_ = f.redis.Wait()
}

// usage is a process's CPU seconds (user + system) and peak resident memory, from /proc.
type usage struct {
	cpu    time.Duration
	peakKB int64
}

func procUsage(pid int) (usage, error) {
	var u usage
	stat, err := os.ReadFile(fmt.Sprintf("/proc/%d/stat", pid))
	if err != nil {
		return u, err
	}
	// Fields after the command name (which may hold spaces) in parentheses.
	rest := string(stat[strings.LastIndexByte(string(stat), ')')+2:])
	fields := strings.Fields(rest)
	utime, _ := strconv.ParseInt(fields[11], 10, 64)
	stime, _ := strconv.ParseInt(fields[12], 10, 64)
	u.cpu = time.Duration(utime+stime) * time.Second / 100 // USER_HZ is 100 on Linux
	status, err := os.ReadFile(fmt.Sprintf("/proc/%d/status", pid))
	if err != nil {
		return u, err
	}
	for _, line := range strings.Split(string(status), "\n") {
		if v, ok := strings.CutPrefix(line, "VmHWM:"); ok {
			u.peakKB, _ = strconv.ParseInt(strings.TrimSuffix(strings.TrimSpace(v), " kB"), 10, 64)
		}
	}
	return u, nil
}
