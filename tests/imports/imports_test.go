// Package imports checks the direction of the module's imports (the READMEs of
// coordinator/, client/, services/ and cmd/ state the same rules): the contract at the
// bottom, the coordinator and the client beside each other and apart, services on the
// client, the commands on top.
package imports

import (
	"bytes"
	"encoding/json"
	"fmt"
	"io"
	"os/exec"
	"path/filepath"
	"runtime"
	"slices"
	"strings"
	"testing"
)

const module = "photonfarm"

// A rule forbids the packages under from (a path below the module, "" for all) to
// depend on, directly or through others, any package under one of forbidden; or, when
// only is set, on any package of the module outside only.
type rule struct {
	from      string
	forbidden []string
	only      []string
	why       string
}

var rules = []rule{
	{from: "coordinator", forbidden: []string{"client", "services", "cmd", "tests"},
		why: "the coordinator serves clients; it knows none of them"},
	{from: "client", forbidden: []string{"coordinator", "services"},
		why: "the client talks to the coordinator only through the gRPC API"},
	{from: "services", forbidden: []string{"coordinator"},
		why: "services reach the coordinator through client/ or the gRPC API"},
	{from: "contract", only: []string{"proto", "contract"},
		why: "the contract is the bottom layer: the proto and what it declares"},
	{from: "coordinator/builder", forbidden: []string{"coordinator/service"},
		why: "the builder declares the task interface it needs; the wiring asserts the service satisfies it"},
	{from: "coordinator/metrics", forbidden: []string{"client", "coordinator/service"},
		why: "metrics are fed by the service, not the other way round"},
}

// pkg is what go list says of one package.
type pkg struct {
	ImportPath string
	Imports    []string
	Deps       []string
}

func TestImportsRunWithTheGrain(t *testing.T) {
	pkgs := list(t)
	if len(pkgs) < 20 {
		t.Fatalf("go list found %d packages; is the module root right?", len(pkgs))
	}
	for _, v := range violations(pkgs, rules) {
		t.Error(v)
	}
}

// TestViolationsAreFound checks the checker on a made-up module with imports against
// each rule, and one whose name only looks like a forbidden folder.
func TestViolationsAreFound(t *testing.T) {
	pkgs := []pkg{
		{ImportPath: "photonfarm/coordinator/metrics", Imports: []string{"fmt", "photonfarm/client"}, Deps: []string{"fmt", "photonfarm/client", "photonfarm/coordinator/errs"}},
		{ImportPath: "photonfarm/services/dashboard", Imports: []string{"photonfarm/client"}, Deps: []string{"photonfarm/client", "photonfarm/coordinator/errs"}},
		{ImportPath: "photonfarm/client", Imports: []string{"photonfarm/coordinator/errs"}, Deps: []string{"photonfarm/coordinator/errs"}},
		{ImportPath: "photonfarm/contract/rules", Imports: []string{"photonfarm/proto/renderfarm/v1", "photonfarm/coordinator/errs"}, Deps: []string{"photonfarm/proto/renderfarm/v1", "photonfarm/coordinator/errs"}},
		{ImportPath: "photonfarm/coordinator/builder", Imports: []string{"photonfarm/coordinator/service"}, Deps: []string{"photonfarm/coordinator/service"}},
		{ImportPath: "photonfarm/coordinator", Imports: []string{"photonfarm/clientele"}, Deps: []string{"photonfarm/clientele"}},
	}
	got := violations(pkgs, rules)
	want := []string{
		"photonfarm/coordinator/metrics imports photonfarm/client: " + rules[0].why,
		"photonfarm/coordinator/metrics imports photonfarm/client: " + rules[5].why,
		"photonfarm/services/dashboard depends on photonfarm/coordinator/errs (through photonfarm/client): " + rules[2].why,
		"photonfarm/client imports photonfarm/coordinator/errs: " + rules[1].why,
		"photonfarm/contract/rules imports photonfarm/coordinator/errs: " + rules[3].why,
		"photonfarm/coordinator/builder imports photonfarm/coordinator/service: " + rules[4].why,
	}
	if strings.Join(got, "\n") != strings.Join(want, "\n") {
		t.Errorf("violations:\n%s\nwant:\n%s", strings.Join(got, "\n"), strings.Join(want, "\n"))
	}
}

// violations lists, for every package and every rule that applies to it, each module
// package it depends on against the rule, naming the direct import that brings it in.
func violations(pkgs []pkg, rules []rule) []string {
	byPath := map[string]pkg{}
	for _, p := range pkgs {
		byPath[p.ImportPath] = p
	}
	var out []string
	for _, p := range pkgs {
		for _, r := range rules {
			if !under(p.ImportPath, r.from) {
				continue
			}
			for _, d := range p.Deps {
				if !strings.HasPrefix(d, module+"/") || !r.against(d) {
					continue
				}
				if slices.Contains(p.Imports, d) {
					out = append(out, fmt.Sprintf("%s imports %s: %s", p.ImportPath, d, r.why))
				} else {
					out = append(out, fmt.Sprintf("%s depends on %s (through %s): %s", p.ImportPath, d, via(p, d, byPath), r.why))
				}
			}
		}
	}
	return out
}

func (r rule) against(dep string) bool {
	if r.only != nil {
		return !slices.ContainsFunc(r.only, func(o string) bool { return under(dep, o) })
	}
	return slices.ContainsFunc(r.forbidden, func(f string) bool { return under(dep, f) })
}

// under reports whether import path p is the module's folder dir or below it.
func under(p, dir string) bool {
	base := module + "/" + dir
	return p == base || strings.HasPrefix(p, base+"/")
}

// via names the direct import of p whose dependencies include dep.
func via(p pkg, dep string, byPath map[string]pkg) string {
	for _, imp := range p.Imports {
		if q, ok := byPath[imp]; ok && slices.Contains(q.Deps, dep) {
			return imp
		}
	}
	return "an import"
}

// list runs go list -json over the whole module from its root.
func list(t *testing.T) []pkg {
	t.Helper()
	_, file, _, _ := runtime.Caller(0)
	cmd := exec.Command("go", "list", "-json", "./...")
	cmd.Dir = filepath.Join(filepath.Dir(file), "..", "..")
	var stderr bytes.Buffer
	cmd.Stderr = &stderr
	out, err := cmd.Output()
	if err != nil {
		t.Fatalf("go list: %v: %s", err, stderr.String())
	}
	var pkgs []pkg
	dec := json.NewDecoder(bytes.NewReader(out))
	for {
		var p pkg
		if err := dec.Decode(&p); err == io.EOF {
			return pkgs
		} else if err != nil {
			t.Fatalf("go list output: %v", err)
		}
		pkgs = append(pkgs, p)
	}
}
