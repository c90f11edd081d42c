package main

import (
	"context"
	"io"
	"os"
	"path/filepath"
	"runtime"
	"runtime/debug"
	"strings"
	"testing"
	"time"

	"photonfarm/client/importer"
	"photonfarm/tests/farmtest"
)

func runForTest(t *testing.T, vars map[string]string, args ...string) (code int, stdout, stderr string) {
	t.Helper()
	var out, errb strings.Builder
	e := &env{stdout: &out, stderr: &errb, getenv: func(k string) string { return vars[k] }}
	code = run(context.Background(), args, e)
	return code, out.String(), errb.String()
}

func TestUsageErrorsExitTwoWithOneLine(t *testing.T) {
	for _, args := range [][]string{
		{},
		{"frobnicate"},
		{"submit"},
		{"submit", "a.json", "b.json"},
		{"submit", "a.json", "--no-such-flag"},
		{"render", "a.json", "--workers", "0"},
		{"render", "a.json", "--exposure", "21"},
		{"render", "a.json", "--exposure", "bright"},
		{"fetch"},
		{"help", "nope"},
	} {
		code, _, stderr := runForTest(t, nil, args...)
		if code != exitUsage {
			t.Errorf("farm %q: exit %d, want %d", args, code, exitUsage)
		}
		if len(args) > 0 && strings.Count(stderr, "\n") != 1 {
			t.Errorf("farm %q: stderr %q, want one line", args, stderr)
		}
	}
}

func TestHelpListsEveryVerb(t *testing.T) {
	code, stdout, _ := runForTest(t, nil, "help")
	if code != 0 {
		t.Fatalf("exit %d", code)
	}
	for _, v := range verbs {
		if !strings.Contains(stdout, "  "+v.name) {
			t.Errorf("help does not list %s", v.name)
		}
		code, out, _ := runForTest(t, nil, v.name, "-h")
		if code != 0 || !strings.HasPrefix(out, "usage: farm "+v.name) {
			t.Errorf("farm %s -h: exit %d, output %q", v.name, code, out)
		}
	}
}

func TestFlagsMayFollowArguments(t *testing.T) {
	fs := newFlags("fetch", &env{stdout: &strings.Builder{}})
	out := fs.String("o", ".", "")
	pos, err := parse(fs, []string{"job-1", "-o", "dir"}, 1, 1)
	if err != nil || len(pos) != 1 || pos[0] != "job-1" || *out != "dir" {
		t.Fatalf("parse = %v, %v, -o %q", pos, err, *out)
	}
}

func TestCoordinatorAddress(t *testing.T) {
	for _, tc := range []struct {
		env  map[string]string
		args []string
		want string
	}{
		{nil, nil, "localhost:7070"},
		{map[string]string{"FARM_COORDINATOR": "farm:1"}, nil, "farm:1"},
		{map[string]string{"FARM_COORDINATOR": "farm:1"}, []string{"--coordinator", "other:2"}, "other:2"},
	} {
		e := &env{stdout: &strings.Builder{}, getenv: func(k string) string { return tc.env[k] }}
		fs := newFlags("status", e)
		addr := coordinatorFlag(fs, e)
		if _, err := parse(fs, append(tc.args, "job"), 1, 1); err != nil {
			t.Fatal(err)
		}
		if got := addr(); got != tc.want {
			t.Errorf("env %v args %v: address %q, want %q", tc.env, tc.args, got, tc.want)
		}
	}
}

// validScene is the smallest scene that passes validation: an emitting sphere in view.
const validScene = `{
  "name": "s",
  "camera": {"position": {"x": 0, "y": 1, "z": 5}, "lookAt": {"y": 1}, "up": {"y": 1}, "verticalFovDegrees": 40},
  "film": {"width": 8, "height": 8},
  "materials": [{"name": "l", "emissive": {"radiance": {"r": 1, "g": 1, "b": 1}}}],
  "shapes": [{"material": "l", "sphere": {"center": {}, "radius": 1}}]
}`

// closedAddress is a loopback address where nothing listens.
func closedAddress(t *testing.T) string { return farmtest.ClosedAddress(t) }

func TestSubmitReportsSceneErrorsBeforeTheNetwork(t *testing.T) {
	dir := t.TempDir()
	path := filepath.Join(dir, "s.json")
	os.WriteFile(path, []byte(`{"shapes": [{}, {}, {}, {"mesh": {"path": "meshes/x.obj"}}]}`), 0o644)
	code, stdout, stderr := runForTest(t, nil, "submit", path, "--coordinator", closedAddress(t))
	want := "farm: shapes[3].mesh.path: open meshes/x.obj: no such file or directory\n"
	if code != exitUsage || stderr != want || stdout != "" {
		t.Errorf("exit %d, stdout %q, stderr %q; want exit 2 and %q", code, stdout, stderr, want)
	}
}

func TestUnreachableCoordinatorExitsOne(t *testing.T) {
	code, _, stderr := runForTest(t, nil, "status", "job-1", "--coordinator", closedAddress(t))
	if code != exitFailure || !strings.Contains(stderr, "coordinator unavailable") || strings.Count(stderr, "\n") != 1 {
		t.Errorf("exit %d, stderr %q", code, stderr)
	}
}

// TestRenderChecksTheOutputFolderFirst: an -o that names a file, or a folder that cannot
// be made, is refused at once, before a farm starts (the worker binary would do nothing).
func TestRenderChecksTheOutputFolderFirst(t *testing.T) {
	dir := t.TempDir()
	path := filepath.Join(dir, "s.json")
	os.WriteFile(path, []byte(validScene), 0o644)
	file := filepath.Join(dir, "out.png")
	os.WriteFile(file, []byte("not a folder"), 0o644)
	for _, out := range []string{file, filepath.Join(file, "sub")} {
		start := time.Now()
		code, _, stderr := runForTest(t, nil, "render", path, "-o", out, "--worker-bin", "/bin/true", "--no-dashboard")
		if code != exitUsage || !strings.Contains(stderr, "-o") || strings.Count(stderr, "\n") != 1 {
			t.Errorf("-o %s: exit %d, stderr %q; want exit 2 and one line naming -o", out, code, stderr)
		}
		if took := time.Since(start); took > 5*time.Second {
			t.Errorf("-o %s: refused after %v, want at once", out, took)
		}
	}
	if b, _ := os.ReadFile(file); string(b) != "not a folder" {
		t.Errorf("the file named by -o changed: %q", b)
	}
}

func TestRenderWithoutWorkerBinaryFails(t *testing.T) {
	dir := t.TempDir()
	path := filepath.Join(dir, "s.json")
	os.WriteFile(path, []byte(validScene), 0o644)
	code, _, stderr := runForTest(t, nil, "render", path, "--worker-bin", filepath.Join(dir, "absent"))
	if code != exitUsage || !strings.Contains(stderr, "--worker-bin") {
		t.Errorf("exit %d, stderr %q", code, stderr)
	}
}

// TestMisspellingsGetTheNearestName: a misspelled verb, flag, scene field and enum value
// each get one line naming where (the file, its line and the field path, for a scene) and
// the declared name nearest to it.
func TestMisspellingsGetTheNearestName(t *testing.T) {
	dir := t.TempDir()
	scene := func(name, body string) string {
		path := filepath.Join(dir, name)
		os.WriteFile(path, []byte(body), 0o644)
		return path
	}
	field := scene("field.json", "{\n  \"film\": {\"width\": 8,\n    \"widht\": 8}}")
	enum := scene("enum.json", `{"output": {"toneMap": "TONE_MAP_FILMC"}}`)
	for _, tc := range []struct {
		args []string
		want string
	}{
		{[]string{"rendr", "s.json"}, `farm: unknown verb "rendr" (did you mean "render"?) (see 'farm help')`},
		{[]string{"help", "sumbit"}, `farm: unknown verb "sumbit" (did you mean "submit"?) (see 'farm help')`},
		{[]string{"frobnicate"}, `farm: unknown verb "frobnicate" (see 'farm help')`},
		{[]string{"render", "s.json", "--worker", "2"},
			`farm: render: flag provided but not defined: -worker (did you mean --workers?) (see 'farm render -h')`},
		{[]string{"submit", "s.json", "--cordinator", "x:1"},
			`farm: submit: flag provided but not defined: -cordinator (did you mean --coordinator?) (see 'farm submit -h')`},
		{[]string{"submit", "s.json", "--colour"}, `farm: submit: flag provided but not defined: -colour (see 'farm submit -h')`},
		{[]string{"validate", field}, "farm: " + field + `: line 3:5: film.widht: unknown field "widht" (did you mean "width"?)`},
		{[]string{"plan", field}, "farm: " + field + `: line 3:5: film.widht: unknown field "widht" (did you mean "width"?)`},
		{[]string{"submit", enum, "--coordinator", closedAddress(t)},
			"farm: " + enum + `: line 1:24: output.tone_map: unknown value "TONE_MAP_FILMC" (did you mean "TONE_MAP_FILMIC"?)`},
	} {
		code, _, stderr := runForTest(t, nil, tc.args...)
		if code != exitUsage || stderr != tc.want+"\n" {
			t.Errorf("farm %q: exit %d, stderr %q; want exit 2 and %q", tc.args, code, stderr, tc.want)
		}
	}
}

// TestValidateAndPlanNeedNoCoordinator: $FARM_COORDINATOR names a closed port, and both
// verbs succeed on the project's scenes (with their mesh files) and refuse a bad one with
// its file and field.
func TestValidateAndPlanNeedNoCoordinator(t *testing.T) {
	vars := map[string]string{"FARM_COORDINATOR": closedAddress(t)}
	scenes := filepath.Join(farmtest.RepoRoot(), "scenes")
	small, caustics := filepath.Join(scenes, "test-small.json"), filepath.Join(scenes, "cornell-caustics.json")
	code, stdout, stderr := runForTest(t, vars, "validate", small, caustics)
	if code != exitOK || stdout != small+": ok\n"+caustics+": ok\n" || stderr != "" {
		t.Errorf("validate: exit %d, stdout %q, stderr %q", code, stdout, stderr)
	}
	code, stdout, stderr = runForTest(t, vars, "plan", caustics)
	if code != exitOK || !strings.Contains(stdout, "run   caustic photon map") || !strings.Contains(stdout, "tasks per phase (round 1): emit ") {
		t.Errorf("plan: exit %d, stdout %q, stderr %q", code, stdout, stderr)
	}
	bad := filepath.Join(t.TempDir(), "bad.json")
	data, _ := os.ReadFile(small)
	os.WriteFile(bad, []byte(strings.Replace(string(data), `"radius": 0.5`, `"radius": -0.5`, 1)), 0o644)
	mesh, _ := os.ReadFile(filepath.Join(scenes, "meshes", "octahedron.obj"))
	os.Mkdir(filepath.Join(filepath.Dir(bad), "meshes"), 0o755)
	os.WriteFile(filepath.Join(filepath.Dir(bad), "meshes", "octahedron.obj"), mesh, 0o644)
	for _, verb := range []string{"validate", "plan"} {
		code, stdout, stderr = runForTest(t, vars, verb, bad)
		if want := "farm: " + bad + ": shapes[1].sphere.radius: "; code != exitUsage || !strings.HasPrefix(stderr, want) || stdout != "" {
			t.Errorf("%s of a negative radius: exit %d, stdout %q, stderr %q; want exit 2 and %q...", verb, code, stdout, stderr, want)
		}
	}
}

// TestPlanSaysHowManyVolumePhotonsInHowManyShards: issue 15's `farm plan` of a foggy scene
// states the volume map's photon paths and shards, and plans its emission shards.
func TestPlanSaysHowManyVolumePhotonsInHowManyShards(t *testing.T) {
	path := filepath.Join(t.TempDir(), "fog.json")
	fog := strings.Replace(validScene, `"shapes":`, `"medium": {"sigma": {"sigmaA": {"r": 0.01}, "sigmaS": {"r": 0.05, "g": 0.05, "b": 0.05}}},
  "photons": {"volumePhotons": 30000, "photonsPerShard": 10000},
  "shapes":`, 1)
	os.WriteFile(path, []byte(fog), 0o644)
	code, stdout, stderr := runForTest(t, map[string]string{"FARM_COORDINATOR": closedAddress(t)}, "plan", path)
	for _, want := range []string{
		"  run   volume photon map      30,000 volume photon paths per round in 3 shards: ",
		"shadow rays attenuated; multiple scattering from the volume photon map\n",
		"tasks per phase (round 1): emit 3, build 1, render 1, composite 1\n",
	} {
		if code != exitOK || !strings.Contains(stdout, want) {
			t.Errorf("plan: exit %d, stdout %q, stderr %q; want %q", code, stdout, stderr, want)
		}
	}
}

// TestSubmitWithoutCoordinatorSaysWhatToRun: one line with a hint, exit status 1, well
// within 5 s.
func TestSubmitWithoutCoordinatorSaysWhatToRun(t *testing.T) {
	addr := closedAddress(t)
	start := time.Now()
	code, stdout, stderr := runForTest(t, nil, "submit", filepath.Join(farmtest.RepoRoot(), "scenes", "test-small.json"), "--coordinator", addr)
	if took := time.Since(start); took > 5*time.Second {
		t.Errorf("took %v, want under 5 s", took)
	}
	if code != exitFailure || stdout != "" || strings.Count(stderr, "\n") != 1 || !strings.Contains(stderr, addr) ||
		!strings.Contains(stderr, "coordinator unavailable") || !strings.Contains(stderr, "start one with 'farm coordinator'") {
		t.Errorf("exit %d, stdout %q, stderr %q; want exit 1 and one line naming %s with a hint", code, stdout, stderr, addr)
	}
}

func TestVersion(t *testing.T) {
	for _, args := range [][]string{{"--version"}, {"-version"}, {"version"}} {
		code, stdout, _ := runForTest(t, nil, args...)
		if code != exitOK || !strings.HasPrefix(stdout, "farm "+farmVersion+" (") || strings.Count(stdout, "\n") != 1 {
			t.Errorf("farm %q: exit %d, stdout %q", args, code, stdout)
		}
	}
	info := &debug.BuildInfo{Settings: []debug.BuildSetting{{Key: "vcs.revision", Value: "f537d7e0123456789"}, {Key: "vcs.modified", Value: "true"}}}
	if got, want := versionLine(info), "farm "+farmVersion+" (commit f537d7e, modified; "+runtime.Version()+")"; got != want {
		t.Errorf("versionLine = %q, want %q", got, want)
	}
	if got, want := versionLine(nil), "farm "+farmVersion+" ("+runtime.Version()+")"; got != want {
		t.Errorf("versionLine(nil) = %q, want %q", got, want)
	}
}

// TestOutputsAreNamedAfterTheScene: farm render and farm fetch both name a job's files
// after its display name; a scene file without a name field gets its file's name, so
// that the job's display name (and so farm fetch) agrees with farm render.
func TestOutputsAreNamedAfterTheScene(t *testing.T) {
	dir := t.TempDir()
	for _, tc := range []struct {
		file, body, want string
	}{
		{"named.json", `{"name": "cornell"}`, "cornell"},
		{"nameless.json", `{}`, "nameless"},
		{"dotted.scene.json", `{"name": ""}`, "dotted.scene"},
	} {
		path := filepath.Join(dir, tc.file)
		os.WriteFile(path, []byte(tc.body), 0o644)
		sf, cleanup, err := readScene(t.Context(), io.Discard, path, "", importer.Options{})
		if err != nil {
			t.Fatal(err)
		}
		cleanup()
		if got := sf.Scene.GetName(); got != tc.want {
			t.Errorf("%s: the job's display name would be %q, want %q", tc.file, got, tc.want)
		}
	}
}
