package rules_test

import (
	"os/exec"
	"strings"
	"testing"
)

// TestContractImports checks that the packages under contract/ import, of this module,
// only proto/renderfarm/v1 and each other (contract/README.md), so that the coordinator,
// the client and the services can all use them.
func TestContractImports(t *testing.T) {
	out, err := exec.Command("go", "list", "-f", `{{.ImportPath}}{{range .Imports}} {{.}}{{end}}`, "photonfarm/contract/...").Output()
	if err != nil {
		t.Fatalf("go list: %v", err)
	}
	packages := 0
	for _, line := range strings.Split(strings.TrimSpace(string(out)), "\n") {
		fields := strings.Fields(line)
		packages++
		for _, imp := range fields[1:] {
			own := strings.HasPrefix(imp, "photonfarm/")
			if own && imp != "photonfarm/proto/renderfarm/v1" && !strings.HasPrefix(imp, "photonfarm/contract/") {
				t.Errorf("%s imports %s: contract imports only proto/renderfarm/v1 and contract/...", fields[0], imp)
			}
		}
	}
	if packages < 3 {
		t.Fatalf("go list found %d contract packages:\n%s", packages, out)
	}
}
