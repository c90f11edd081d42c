package scene_test

import (
	"errors"
	"os"
	"path/filepath"
	"strings"
	"testing"

	"google.golang.org/protobuf/encoding/protojson"
	"google.golang.org/protobuf/proto"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	"photonfarm/coordinator/planner"
	pb "photonfarm/proto/renderfarm/v1"
)

// FuzzParseValidatePlan feeds arbitrary bytes to the path a submitted scene takes: parse,
// validate and, if valid, fill in defaults and plan its passes and first round. Whatever
// the bytes, nothing may panic; a refusal must name what is wrong; an accepted scene must
// survive a binary round trip, still validate once its defaults are filled in (which
// changes nothing a second time or in its plan) and plan at least one task. `go test` runs
// the seeds (every scene in scenes/, the scene of every shared vector, a few broken ones
// and what earlier fuzzing found, testdata/fuzz); `make fuzz` (scripts/fuzz.sh, part of `make test`) fuzzes for a bounded
// time.
func FuzzParseValidatePlan(f *testing.F) {
	seeds, _ := filepath.Glob("../../scenes/*.json")
	stiff, _ := filepath.Glob("../../scenes/stiff/*.json")
	for _, path := range append(seeds, stiff...) {
		data, err := os.ReadFile(path)
		if err != nil {
			f.Fatal(err)
		}
		f.Add(data)
	}
	// Every shared vector's scene (not grown), so that each rule is reached from the start.
	vectors, _ := filepath.Glob(filepath.Join(vectorDir, "*.json"))
	for _, path := range vectors {
		data, err := os.ReadFile(path)
		vec := &pb.SceneVector{}
		if err == nil {
			err = protojson.Unmarshal(data, vec)
		}
		if err != nil {
			f.Fatalf("%s: %v", path, err)
		}
		if data, err = protojson.Marshal(vec.GetScene()); err != nil {
			f.Fatal(err)
		}
		f.Add(data)
	}
	for _, s := range []string{"", "{", "null", "[]", `{"film":{"width":-1}}`, `{"name":"\u0000"}`,
		`{"camera":{"position":{"x":"NaN"}}}`, `{"film":{"width":4294967295,"height":4294967295}}`} {
		f.Add([]byte(s))
	}
	f.Fuzz(func(t *testing.T, data []byte) {
		sc, err := scene.ParseJSON(data)
		if err != nil {
			if !strings.HasPrefix(err.Error(), "scene: ") || len(err.Error()) <= len("scene: ") {
				t.Fatalf("parse error %q does not say what is wrong", err)
			}
			return
		}
		if err := scene.Validate(sc); err != nil {
			var fe *scene.FieldError
			if !errors.As(err, &fe) || fe.Field == "" || fe.Message == "" {
				t.Fatalf("validation error %#v does not name a field and a reason", err)
			}
			return
		}
		b, err := proto.Marshal(sc)
		if err != nil {
			t.Fatalf("a valid scene does not marshal: %v", err)
		}
		back := sc.ProtoReflect().New().Interface()
		if err := proto.Unmarshal(b, back); err != nil || !proto.Equal(sc, back) {
			t.Fatalf("a valid scene does not survive a binary round trip: %v", err)
		}
		d := scene.Defaults(sc)
		if err := scene.Validate(d); err != nil {
			t.Fatalf("a valid scene with its defaults filled in is refused: %v", err)
		}
		if !proto.Equal(scene.Defaults(d), d) {
			t.Fatal("Defaults changes a scene whose defaults are filled in")
		}
		if planner.Passes(sc) == nil {
			t.Fatal("a valid scene has no passes")
		}
		checkRound(t, sc, d)
	})
}

// smallRound is the most tasks the fuzzer plans. The largest round Validate allows
// (max_tiles_per_round tiles and max_shards_per_map shards per map) plans in tens of
// milliseconds (TestPlanLargestRoundStaysWithinLimits): planning such rounds for every
// mutation of a large film would slow the fuzzer a hundredfold, so of those only the
// bounds are checked.
const smallRound = 2048

// checkRound checks the first round of sc (valid) and of d, sc with its defaults: the
// tasks a round may have are bounded by the scene limits, and small rounds are planned,
// the same with or without the defaults.
func checkRound(t *testing.T, sc, d *pb.Scene) {
	tiles, shards := scene.TilesPerRound(sc), uint64(0)
	for _, m := range scene.PhotonMaps(sc) {
		n := scene.ShardsPerMap(sc, m.Photons)
		if n > rules.Scene.GetMaxShardsPerMap() {
			t.Fatalf("a valid scene has %d shards in its %s map", n, m.Name())
		}
		shards += n
	}
	if tiles > rules.Scene.GetMaxTilesPerRound() {
		t.Fatalf("a valid scene has %d tiles per round", tiles)
	}
	// Tiles, a composite; shards, a build; as many precompute tasks as global shards, a merge.
	if bound := tiles + 1 + 2*shards + 2; bound > smallRound {
		return
	}
	tasks := planner.Plan(sc)
	if len(tasks) == 0 || uint64(len(tasks)) > tiles+1+2*shards+2 {
		t.Fatalf("a valid scene with %d tiles and %d shards plans %d tasks", tiles, shards, len(tasks))
	}
	withDefaults := planner.Plan(d)
	if len(withDefaults) != len(tasks) {
		t.Fatalf("the plan has %d tasks, %d once defaults are filled in", len(tasks), len(withDefaults))
	}
	for i := range tasks {
		if !proto.Equal(tasks[i], withDefaults[i]) {
			t.Fatalf("task %d is %v, %v once defaults are filled in", i, tasks[i], withDefaults[i])
		}
	}
}
