package integration

import (
	"context"
	"encoding/json"
	"os"
	"os/exec"
	"path/filepath"
	"strings"
	"syscall"
	"testing"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/client"
	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// smallSceneJSON returns scenes/test-small.json as a generic JSON tree, its mesh path
// made absolute so that the scene works from any folder given the asset root
// scenesRoot (the mesh is outside the folder the test writes the scene to).
func smallSceneJSON(t *testing.T) map[string]any {
	t.Helper()
	root := farmtest.RepoRoot()
	b, err := os.ReadFile(filepath.Join(root, "scenes", "test-small.json"))
	if err != nil {
		t.Fatal(err)
	}
	var m map[string]any
	if err := json.Unmarshal(b, &m); err != nil {
		t.Fatal(err)
	}
	mesh := m["shapes"].([]any)[3].(map[string]any)["mesh"].(map[string]any)
	mesh["path"] = filepath.Join(root, "scenes", mesh["path"].(string))
	return m
}

// scenesRoot is the repository's scenes folder, the asset root of smallSceneJSON's scenes.
func scenesRoot() string { return filepath.Join(farmtest.RepoRoot(), "scenes") }

func shape(m map[string]any, i int) map[string]any {
	return m["shapes"].([]any)[i].(map[string]any)
}

func TestMalformedScenesRefused(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	dir := t.TempDir()

	for _, tc := range []struct {
		name string
		// Either raw text or a change to the valid scene.
		raw    string
		change func(m map[string]any)
		// What the one line on stderr must contain.
		want string
		// Whether the scene parses, so that it can be sent with a raw SubmitJob too.
		rpc bool
		// Whether the mesh path is relative to the scene's folder, the default asset root
		// (else scenesRoot is).
		relative bool
	}{
		{name: "bad JSON", raw: `{"name": "broken",, "film": {}}`, want: "bad-JSON.json: line 1:19: unexpected token"},
		{name: "unknown field", change: func(m map[string]any) {
			sphere := shape(m, 1)["sphere"].(map[string]any)
			sphere["radus"] = sphere["radius"]
			delete(sphere, "radius")
		}, want: `unknown-field.json: line 103:9: shapes[1].sphere.radus: unknown field "radus" (did you mean "radius"?)`},
		{name: "negative radius", change: func(m map[string]any) {
			shape(m, 2)["sphere"].(map[string]any)["radius"] = -1
		}, want: "shapes[2].sphere.radius: ", rpc: true},
		{name: "NaN coordinate", change: func(m map[string]any) {
			shape(m, 1)["sphere"].(map[string]any)["center"].(map[string]any)["y"] = "NaN"
		}, want: "shapes[1].sphere.center.y: ", rpc: true},
		{name: "missing mesh file", change: func(m map[string]any) {
			shape(m, 3)["mesh"].(map[string]any)["path"] = "meshes/absent.obj"
		}, want: "shapes[3].mesh.path: open meshes/absent.obj: no such file or directory", relative: true},
		{name: "zero resolution", change: func(m map[string]any) {
			m["film"].(map[string]any)["width"] = 0
		}, want: "film.width: ", rpc: true},
	} {
		t.Run(tc.name, func(t *testing.T) {
			text := []byte(tc.raw)
			if tc.change != nil {
				m := smallSceneJSON(t)
				tc.change(m)
				var err error
				if text, err = json.MarshalIndent(m, "", "  "); err != nil {
					t.Fatal(err)
				}
			}
			path := filepath.Join(dir, strings.ReplaceAll(tc.name, " ", "-")+".json")
			if err := os.WriteFile(path, text, 0o644); err != nil {
				t.Fatal(err)
			}

			// The CLI: exit status 2, one line on stderr naming the field, no job id.
			args := []string{"submit", path, "--coordinator", f.Addr}
			if !tc.relative {
				args = append(args, "--asset-root", scenesRoot())
			}
			code, stdout, stderr := farmtest.RunFarm(t, 30*time.Second, nil, args...)
			lines := strings.Split(strings.TrimRight(stderr, "\n"), "\n")
			if code != 2 {
				t.Errorf("farm submit: exit status %d, want 2", code)
			}
			if len(lines) != 1 || !strings.HasPrefix(lines[0], "farm: ") || !strings.Contains(lines[0], tc.want) {
				t.Errorf("farm submit: stderr %q, want one line `farm: ...%s...`", stderr, tc.want)
			}
			if stdout != "" {
				t.Errorf("farm submit: stdout %q, want nothing", stdout)
			}

			// A raw SubmitJob of the parsed scene: INVALID_ARGUMENT naming the field.
			if !tc.rpc {
				return
			}
			sc, err := scene.ParseJSON(text)
			if err != nil {
				t.Fatalf("the scene does not parse: %v", err)
			}
			sf, err := client.ReadSceneFile(context.Background(), path, client.WithAssetRoot(scenesRoot())) // mesh path -> digest, as a client would
			if err != nil {
				t.Fatal(err)
			}
			if err := f.Client.Upload(context.Background(), sf); err != nil {
				t.Fatal(err)
			}
			sc = sf.Scene
			_, err = f.Client.Jobs().SubmitJob(context.Background(), &pb.SubmitJobRequest{Scene: sc})
			if st, _ := status.FromError(err); st.Code() != codes.InvalidArgument || !strings.Contains(st.Message(), tc.want) {
				t.Errorf("SubmitJob: %v; want InvalidArgument containing %q", err, tc.want)
			}
		})
	}

	jobs, err := f.Client.ListJobs(context.Background())
	if err != nil || len(jobs) != 0 {
		t.Fatalf("after refused submissions ListJobs = %v, %v; want no jobs", jobs, err)
	}

	// The valid scene goes through the same path: one job, its id on stdout.
	text, _ := json.Marshal(smallSceneJSON(t))
	path := filepath.Join(dir, "valid.json")
	os.WriteFile(path, text, 0o644)
	code, stdout, stderr := farmtest.RunFarm(t, 30*time.Second, []string{"FARM_COORDINATOR=" + f.Addr}, "submit", path, "--asset-root", scenesRoot())
	if code != 0 {
		t.Fatalf("farm submit of a valid scene: exit status %d, stderr %q", code, stderr)
	}
	jobs, err = f.Client.ListJobs(context.Background())
	if err != nil || len(jobs) != 1 || jobs[0].GetId() != strings.TrimSpace(stdout) {
		t.Errorf("after a valid submit: stdout %q, ListJobs = %v, %v; want that one job", stdout, jobs, err)
	}
}

// farmRender runs `farm render` as a process of its own with TMPDIR set to a folder of
// the test's, so the test can check that the temporary farm folder is removed.
func farmRender(t *testing.T, args ...string) (cmd *exec.Cmd, stdout, stderr *farmtest.SyncBuffer, tmp string) {
	t.Helper()
	return farmCommand(t, append([]string{"render"}, args...)...)
}

// farmCommand starts `farm ARGS...` as farmRender does, in a process group of its own.
func farmCommand(t *testing.T, args ...string) (cmd *exec.Cmd, stdout, stderr *farmtest.SyncBuffer, tmp string) {
	t.Helper()
	tmp = t.TempDir()
	cmd = exec.Command(filepath.Join(farmtest.BinDir(t), "farm"), args...)
	cmd.Env = append(os.Environ(), "TMPDIR="+tmp)
	stdout, stderr = &farmtest.SyncBuffer{}, &farmtest.SyncBuffer{}
	cmd.Stdout, cmd.Stderr = stdout, stderr
	cmd.SysProcAttr = &syscall.SysProcAttr{Setpgid: true}
	if err := cmd.Start(); err != nil {
		t.Fatal(err)
	}
	t.Cleanup(func() { syscall.Kill(-cmd.Process.Pid, syscall.SIGKILL) })
	return cmd, stdout, stderr, tmp
}

func waitTimeout(t *testing.T, cmd *exec.Cmd, d time.Duration) int {
	t.Helper()
	done := make(chan error, 1)
	go func() { done <- cmd.Wait() }()
	select {
	case err := <-done:
		if ee, ok := err.(*exec.ExitError); ok {
			return ee.ExitCode()
		} else if err != nil {
			t.Fatal(err)
		}
		return 0
	case <-time.After(d):
		syscall.Kill(-cmd.Process.Pid, syscall.SIGKILL)
		t.Fatalf("farm %s did not finish within %s", strings.Join(cmd.Args[1:], " "), d)
		return -1
	}
}

// processesMentioning lists the running processes whose command line contains s.
func processesMentioning(s string) []string {
	var found []string
	dirs, _ := filepath.Glob("/proc/[0-9]*/cmdline")
	for _, d := range dirs {
		b, err := os.ReadFile(d)
		if err == nil && strings.Contains(string(b), s) {
			found = append(found, strings.ReplaceAll(string(b), "\x00", " "))
		}
	}
	return found
}

// leftovers lists what the farm left in its TMPDIR.
func leftovers(t *testing.T, tmp string) []string {
	entries, err := os.ReadDir(tmp)
	if err != nil {
		t.Fatal(err)
	}
	var names []string
	for _, e := range entries {
		names = append(names, e.Name())
	}
	return names
}

func TestFarmRenderWritesEXRAndPNG(t *testing.T) {
	out := filepath.Join(t.TempDir(), "out")
	scenePath := filepath.Join(farmtest.RepoRoot(), "scenes", "test-small.json")
	// No --worker-bin: farm finds farm-worker next to itself. 20 stops down, the lamp (12
	// per channel) is below half an 8-bit step of the preview; the EXR stays linear.
	cmd, stdout, stderr, tmp := farmRender(t, scenePath, "-o", out, "--workers", "2", "--exposure", "-20")
	if code := waitTimeout(t, cmd, 90*time.Second); code != 0 {
		t.Fatalf("farm render: exit status %d\nstdout: %s\nstderr: %s", code, stdout, stderr)
	}
	exr, err := os.ReadFile(filepath.Join(out, "test-small.exr"))
	if err != nil {
		t.Fatal(err)
	}
	if err := checkFinalEXR(exr, 64, 48, 16); err != nil {
		t.Error(err)
	}
	if err := checkEXRMetadata(exr, 8, 1); err != nil {
		t.Error(err)
	}
	png, err := os.ReadFile(filepath.Join(out, "test-small.png"))
	if err != nil {
		t.Fatal(err)
	}
	if w, h, err := pngSize(png); err != nil || w != 64 || h != 48 {
		t.Errorf("test-small.png: %dx%d, %v; want 64x48", w, h, err)
	}
	if lit, covered, err := pngLitAndCovered(png); err != nil || lit != 0 || covered == 0 {
		t.Errorf("test-small.png at --exposure -20: %d pixels with colour, %d with alpha (%v); want none and some", lit, covered, err)
	}
	if left := leftovers(t, tmp); len(left) != 0 {
		t.Errorf("farm render left %v in its temporary folder", left)
	}
	if procs := processesMentioning(tmp); len(procs) != 0 {
		t.Errorf("still running after farm render exited: %q", procs)
	}
	if !strings.Contains(stdout.String(), filepath.Join(out, "test-small.exr")) {
		t.Errorf("stdout does not name the EXR: %q", stdout)
	}
}

// TestFarmRenderReportMeasuresEveryRoundAgainstTheReference: `farm render --report` prints
// the job's rounds when it ends. A two-round job rendered a second time with the first
// job's image as its reference: the same seed gives the same rounds, so the second job's
// round 2 is the reference exactly (RMSE 0) and its round 1, a round short, is not.
func TestFarmRenderReportMeasuresEveryRoundAgainstTheReference(t *testing.T) {
	dir := t.TempDir()
	m := smallSceneJSON(t)
	m["progressive"] = map[string]any{"maxRounds": 2}
	render := func(name string) string {
		t.Helper()
		text, _ := json.Marshal(m)
		scenePath := filepath.Join(dir, name+".json")
		if err := os.WriteFile(scenePath, text, 0o644); err != nil {
			t.Fatal(err)
		}
		cmd, stdout, stderr, _ := farmRender(t, scenePath, "-o", dir, "--name", name, "--workers", "2",
			"--no-dashboard", "--report", "--asset-root", "/")
		if code := waitTimeout(t, cmd, 120*time.Second); code != 0 {
			t.Fatalf("farm render %s: exit status %d\nstdout: %s\nstderr: %s", name, code, stdout, stderr)
		}
		return stdout.String()
	}
	first := render("first")
	if !strings.Contains(first, "succeeded, 2 rounds") || !strings.Contains(first, "estimated error") {
		t.Errorf("farm render --report without a reference printed %q; want the job's two rounds", first)
	}
	m["progressive"].(map[string]any)["reference"] = map[string]any{"path": filepath.Join(dir, "first.exr")}
	second := render("second")
	rows := map[string][]string{}
	for _, line := range strings.Split(second, "\n") {
		if f := strings.Fields(line); len(f) >= reportColumns && (f[0] == "1" || f[0] == "2") {
			rows[f[0]] = f
		}
	}
	if len(rows) != 2 {
		t.Fatalf("farm render --report printed %q; want a row for each of rounds 1 and 2", second)
	}
	if got := rows["2"][reportReferenceColumn]; got != "0" && got != "0.0000" {
		t.Errorf("round 2's reference RMSE = %s, want 0: the same seed renders the reference again (%q)", got, second)
	}
	if got := rows["1"][reportReferenceColumn]; got == "-" || got == "0" || got == "0.0000" {
		t.Errorf("round 1's reference RMSE = %s, want above 0: one round short of the reference (%q)", got, second)
	}
}

func TestFarmRenderInterruptedStopsTheFarm(t *testing.T) {
	out := filepath.Join(t.TempDir(), "out")
	// A scene too slow to finish before the interrupt.
	m := smallSceneJSON(t)
	m["film"] = map[string]any{"width": 256, "height": 192, "tileSize": 32}
	m["sampling"].(map[string]any)["samplesPerPixel"] = 1024
	text, _ := json.Marshal(m)
	scenePath := filepath.Join(t.TempDir(), "slow.json")
	os.WriteFile(scenePath, text, 0o644)

	cmd, stdout, stderr, tmp := farmRender(t, scenePath, "-o", out, "--workers", "2", "--asset-root", scenesRoot())
	// Interrupt once the job is under way (its id has been printed).
	deadline := time.Now().Add(30 * time.Second)
	for !strings.Contains(stdout.String(), "as job") {
		if time.Now().After(deadline) {
			t.Fatalf("farm render did not start the job within 30s\nstdout: %s\nstderr: %s", stdout, stderr)
		}
		time.Sleep(20 * time.Millisecond)
	}
	time.Sleep(300 * time.Millisecond)
	syscall.Kill(cmd.Process.Pid, syscall.SIGINT)
	code := waitTimeout(t, cmd, 60*time.Second)
	if code != 130 {
		t.Errorf("farm render after SIGINT: exit status %d, want 130\nstderr: %s", code, stderr)
	}
	if left := leftovers(t, tmp); len(left) != 0 {
		t.Errorf("farm render left %v in its temporary folder", left)
	}
	// No worker survives (their cache folders are under TMPDIR, so their command lines
	// name it).
	if procs := processesMentioning(tmp); len(procs) != 0 {
		t.Errorf("still running after farm render exited: %q", procs)
	}
	if _, err := os.Stat(filepath.Join(out, "slow.exr")); err == nil {
		t.Errorf("an interrupted render wrote an image")
	}
}

// TestSubmitWithoutCoordinatorFailsInOneLineWithinFiveSeconds: the built farm, pointed
// by $FARM_COORDINATOR at a port where nothing listens, prints one line naming the
// address with what to run, and exits 1 within 5 s (RunFarm fails the test after that).
func TestSubmitWithoutCoordinatorFailsInOneLineWithinFiveSeconds(t *testing.T) {
	addr := farmtest.ClosedAddress(t)
	scene := filepath.Join(farmtest.RepoRoot(), "scenes", "test-small.json")
	code, stdout, stderr := farmtest.RunFarm(t, 5*time.Second, []string{"FARM_COORDINATOR=" + addr}, "submit", scene)
	if code != 1 || stdout != "" || strings.Count(stderr, "\n") != 1 || !strings.Contains(stderr, addr) ||
		!strings.Contains(stderr, "start one with 'farm coordinator'") {
		t.Errorf("exit %d, stdout %q, stderr %q; want exit 1 and one line naming %s with a hint", code, stdout, stderr, addr)
	}
}
