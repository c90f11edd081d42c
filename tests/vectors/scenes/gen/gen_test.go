package main

import (
	"regexp"
	"sort"
	"strings"
	"testing"

	"photonfarm/tests/vectors/vectorfiles"
)

const root = "../../../.."

// TestCommittedVectorsAreCurrent fails while the committed vectors (and their assets)
// differ from what the generator makes.
func TestCommittedVectorsAreCurrent(t *testing.T) {
	files, err := Vectors(root)
	if err != nil {
		t.Fatal(err)
	}
	vectorfiles.Check(t, root, files, "go run ./tests/vectors/scenes/gen", owned)
}

// notExpressible are accepted keys no vector can hold, and why.
var notExpressible = map[string]string{
	// grow copies the last element, and material, mesh and texture names must be unique:
	// the most a scene may have would have to be written out.
	"Scene.materials:max_items=": "needs that many distinct names",
	"Scene.meshes:max_items=":    "needs that many distinct names",
	"Scene.textures:max_items=":  "needs that many distinct names",
}

// TestEveryRuleHasAVector computes from the descriptors every check a scene must pass
// (ruleKeys) and fails if no refused vector covers one of them, or no accepted vector an
// inclusive bound or a default; and if a case claims a key that is not a check of the
// contract, or of the wrong kind.
func TestEveryRuleHasAVector(t *testing.T) {
	wantRefused, wantAccepted := ruleKeys()
	gotRefused, gotAccepted := map[string]bool{}, map[string]bool{}
	for _, c := range refused {
		for _, k := range c.covers {
			if !wantRefused[k] {
				t.Errorf("%s covers %q, which is not a refusal the contract declares", c.name, k)
			}
			gotRefused[k] = true
		}
	}
	for _, c := range accepted {
		for _, k := range c.covers {
			if !wantAccepted[k] {
				t.Errorf("%s covers %q, which is not an acceptance the contract declares", c.name, k)
			}
			gotAccepted[k] = true
		}
	}
	for _, missing := range missingKeys(wantRefused, gotRefused, nil) {
		t.Errorf("no refused vector covers %s", missing)
	}
	for _, missing := range missingKeys(wantAccepted, gotAccepted, notExpressible) {
		t.Errorf("no accepted vector covers %s", missing)
	}
	t.Logf("%d refused cases cover %d checks; %d accepted cases (and the scene files) cover %d of %d",
		len(refused), len(gotRefused), len(accepted), len(gotAccepted), len(wantAccepted))
}

func missingKeys(want, got map[string]bool, except map[string]string) []string {
	var missing []string
	for k := range want {
		if _, ok := except[k]; !got[k] && !ok {
			missing = append(missing, k)
		}
	}
	sort.Strings(missing)
	return missing
}

// TestCasesSayWhatTheyAre checks the table itself: kebab-case names that start with what
// happens to the scene, and refusals at a field that the key they cover names.
func TestCasesSayWhatTheyAre(t *testing.T) {
	kebab := regexp.MustCompile(`^(accept|refuse)(-[a-z0-9]+)+$`)
	for _, c := range append(append([]vectorCase(nil), refused...), accepted...) {
		if !kebab.MatchString(c.name) || strings.HasPrefix(c.name, "refuse-") != (c.refused != "") {
			t.Errorf("%s: want a kebab-case name starting refuse- for a refusal (field %q) and accept- otherwise", c.name, c.refused)
		}
		segments := strings.Split(regexp.MustCompile(`\[\d+\]`).ReplaceAllString(c.refused, ""), ".")
		for _, k := range c.covers {
			field, _, _ := strings.Cut(k[strings.Index(k, ".")+1:], ":")
			if c.refused != "" && !strings.HasSuffix(k, ":one_required") && !contains(segments, field) {
				t.Errorf("%s covers %s but is refused at %s, which does not name %s", c.name, k, c.refused, field)
			}
		}
	}
}

func contains(list []string, s string) bool {
	for _, x := range list {
		if x == s {
			return true
		}
	}
	return false
}
