// Package tasks reads what proto/renderfarm/v1 declares about the work of a job: the
// phases in the order a round runs them, who runs each and what it reads and makes
// (phase_info), the artifact names (artifact_info), which Task.spec belongs to which
// phase (task_phase), and how each failure kind is treated (failure_info). The worker and
// the dashboard read the same options (worker/contract, services/dashboard/web/src/
// contract.gen.ts), so none of these facts is written twice.
package tasks

import (
	"fmt"
	"strings"

	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/reflect/protoreflect"

	pb "photonfarm/proto/renderfarm/v1"
)

// Phase is one phase as the contract declares it.
type Phase struct {
	Phase pb.Phase
	// Rank is the phase's place in a round, from 1, in the order the Phase enum declares
	// its values: what stages run in, whatever the values' numbers.
	Rank     int
	Label    string
	Executor pb.Executor
	Inputs   []pb.ArtifactKind
	Outputs  []pb.ArtifactKind
}

// Table is a job's phases in the order a round runs them.
type Table []Phase

// Phases is the contract's table (job.proto's Phase enum).
var Phases = TableOf(pb.Phase(0).Descriptor())

// TableOf reads the phase table from a Phase-like enum: every value but 0, in declaration
// order, with its phase_info. It panics if a value lacks phase_info or an input is made by
// no phase before it: the contract is then broken, and nothing can run.
func TableOf(ed protoreflect.EnumDescriptor) Table {
	var t Table
	made := map[pb.ArtifactKind]bool{}
	values := ed.Values()
	for i := 0; i < values.Len(); i++ {
		v := values.Get(i)
		if v.Number() == 0 {
			continue
		}
		info, ok := valueInfo[*pb.PhaseInfo](v, pb.E_PhaseInfo)
		if !ok {
			panic(fmt.Sprintf("tasks: phase %s declares no phase_info", v.Name()))
		}
		for _, in := range info.GetInputs() {
			if !made[in] && !Artifact(in).PreviousRound {
				panic(fmt.Sprintf("tasks: phase %s reads %s, which no phase before it makes", v.Name(), in))
			}
		}
		for _, out := range info.GetOutputs() {
			made[out] = true
		}
		t = append(t, Phase{
			Phase: pb.Phase(v.Number()), Rank: len(t) + 1, Label: info.GetLabel(),
			Executor: info.GetExecutor(), Inputs: info.GetInputs(), Outputs: info.GetOutputs(),
		})
	}
	return t
}

// Of returns phase p's entry, and false if the table has none (an unknown number).
func (t Table) Of(p pb.Phase) (Phase, bool) {
	for _, ph := range t {
		if ph.Phase == p {
			return ph, true
		}
	}
	return Phase{}, false
}

// Rank returns p's place in a round (from 1), or 0 for an unknown phase.
func (t Table) Rank(p pb.Phase) int {
	ph, _ := t.Of(p)
	return ph.Rank
}

// RunBy lists the phases executor e leases, in round order.
func (t Table) RunBy(e pb.Executor) []pb.Phase {
	var out []pb.Phase
	for _, ph := range t {
		if ph.Executor == e {
			out = append(out, ph.Phase)
		}
	}
	return out
}

// Rank returns p's place in a round in the contract's table (0 for an unknown phase).
func Rank(p pb.Phase) int { return Phases.Rank(p) }

// Label returns p's label for people ("Render tiles"), or the enum name for an unknown
// phase.
func Label(p pb.Phase) string {
	if ph, ok := Phases.Of(p); ok {
		return ph.Label
	}
	return p.String()
}

// Name is a phase's short name for people and metrics: "render", "composite".
func Name(p pb.Phase) string { return lowerSuffix(p.String(), "PHASE_") }

// JobStateName is a job state for people: "succeeded", "running".
func JobStateName(s pb.JobState) string { return lowerSuffix(s.String(), "JOB_STATE_") }

// TaskStateName is a task state for people: "leased", "succeeded".
func TaskStateName(s pb.TaskState) string { return lowerSuffix(s.String(), "TASK_STATE_") }

func lowerSuffix(s, prefix string) string { return strings.ToLower(strings.TrimPrefix(s, prefix)) }

// SpecPhase returns the phase whose tasks carry spec field fd of Task (its task_phase).
func SpecPhase(fd protoreflect.FieldDescriptor) pb.Phase {
	opts := fd.Options()
	if opts == nil {
		return pb.Phase_PHASE_UNSPECIFIED
	}
	return proto.GetExtension(opts, pb.E_TaskPhase).(pb.Phase)
}

// PhaseOf returns the phase of task t's spec, or PHASE_UNSPECIFIED if none is set.
func PhaseOf(t *pb.Task) pb.Phase {
	od := t.ProtoReflect().Descriptor().Oneofs().ByName("spec")
	fd := t.ProtoReflect().WhichOneof(od)
	if fd == nil {
		return pb.Phase_PHASE_UNSPECIFIED
	}
	return SpecPhase(fd)
}
