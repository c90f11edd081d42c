package main

import (
	"context"
	"fmt"
	"io"
	"strings"
	"text/tabwriter"

	"photonfarm/contract/scene"
	"photonfarm/contract/tasks"
	"photonfarm/coordinator/planner"
	pb "photonfarm/proto/renderfarm/v1"
)

var planVerb = &verb{
	name:    "plan",
	args:    "SCENE|MODEL [--asset-root DIR] [--width N] [--height N]",
	summary: "print the passes a scene would run and skip, and why, without rendering (no coordinator needed)",
	run:     runPlan,
}

func runPlan(ctx context.Context, e *env, args []string) error {
	fs := newFlags("plan", e)
	assetRoot := assetRootFlag(fs)
	imports := importFlags(fs)
	pos, err := parse(fs, args, 1, 1)
	if err != nil {
		return err
	}
	sf, cleanup, err := checkScene(ctx, e.stdout, pos[0], *assetRoot, imports())
	if err != nil {
		return err
	}
	defer cleanup()
	sc := scene.Defaults(sf.Scene)
	// The coordinator's own planner, so the plan is the one SubmitJob would make (with
	// this build's planner: a coordinator of another version may plan otherwise).
	fmt.Fprintf(e.stdout, "plan of %s\n", pos[0])
	printPlan(e.stdout, planner.Passes(sc), planner.PhaseCounts(planner.Plan(sc)))
	return nil
}

// printPlan writes one line per pass (run or skip, and why), then the tasks per phase of
// the first round.
func printPlan(w io.Writer, plan *pb.Plan, phases []*pb.PhaseProgress) {
	tw := tabwriter.NewWriter(w, 0, 4, 2, ' ', 0)
	for _, p := range plan.GetPasses() {
		verdict := "skip"
		if p.GetEnabled() {
			verdict = "run"
		}
		fmt.Fprintf(tw, "  %s\t%s\t%s\n", verdict, printable(p.GetName()), oneLine(p.GetReason()))
	}
	tw.Flush()
	if len(phases) == 0 {
		return
	}
	var parts []string
	for _, ph := range phases {
		parts = append(parts, fmt.Sprintf("%s %d", tasks.Name(ph.GetPhase()), ph.GetTasksTotal()))
	}
	fmt.Fprintf(w, "tasks per phase (round 1): %s\n", strings.Join(parts, ", "))
}
