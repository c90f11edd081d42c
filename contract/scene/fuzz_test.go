package scene_test

import (
	"errors"
	"os"
	"path/filepath"
	"strings"
	"testing"

	"google.golang.org/protobuf/proto"

	"photonfarm/contract/scene"
	"photonfarm/coordinator/planner"
)

// FuzzParseValidatePlan feeds arbitrary bytes to the path a submitted scene takes: parse,
// validate and, if valid, plan its passes and first round. Whatever the bytes, nothing may
// panic; a refusal must name what is wrong; an accepted scene must survive a binary round
// trip and plan at least one task. `go test` runs the seeds (every scene in scenes/ and a
// few broken ones); `make fuzz` (part of `make test`) fuzzes for a bounded time.
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
		if planner.Passes(sc) == nil || len(planner.Plan(sc)) == 0 {
			t.Fatal("a valid scene plans no work")
		}
	})
}
