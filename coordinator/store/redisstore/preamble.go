package redisstore

import (
	"fmt"
	"strings"

	"google.golang.org/protobuf/reflect/protoreflect"

	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
)

// preamble is the head of every script: the facts the Lua library shares with Go, written
// out from Go so that the two cannot drift. The task and job state numbers and names and
// the failure kind numbers come from the pb enums (and the kinds that blame no worker from
// their failure_info), the key names and the job record's field prefixes from keys.go, the
// promote batch from lease.go. (Stages are not among them: Go computes each task's stage,
// store.Stage, and passes it with the task, so Lua only compares them.)
//
// Why a generated preamble rather than KEYS and ARGV alone: a lease discovers the keys it
// needs while it runs (which job is ready, then its queue), so they cannot all be named
// in KEYS beforehand, and the state numbers are used in every script; a preamble built
// once at start-up costs nothing per call and keeps each script's ARGV to its own
// arguments.
var preamble = buildPreamble()

func buildPreamble() string {
	var b strings.Builder
	b.WriteString("local P = ARGV[1]\nlocal NOW_S = ARGV[2]\nlocal NOW = tonumber(NOW_S)\n")
	enumLocals(&b, pb.TaskState(0).Descriptor(), "TASK_STATE_", "", "TASK_STATES")
	enumLocals(&b, pb.JobState(0).Descriptor(), "JOB_STATE_", "J", "JOB_STATES")
	enumLocals(&b, pb.FailureKind(0).Descriptor(), "FAILURE_KIND_", "F", "")
	for _, k := range []struct{ local, name string }{
		{"SEQ", seqKey}, {"JOBS", jobsKey}, {"REQUESTS", requestsKey}, {"LEASES", leasesKey}, {"DELAYED", delayedKey}, {"PENDING", pendingKey}, {"ENDED", endedKey}, {"DOOMED", doomedKey}, {"CHANGES", changesKey},
		{"WORKERS", workersKey}, {"SEEN", seenKey}, {"HOLDERS", holdersKey}, {"WSEQ", wseqKey},
	} {
		fmt.Fprintf(&b, "local %s = P .. %s\n", k.local, lua(k.name))
	}
	fmt.Fprintf(&b, "local BLOCKED, FAILURES = %s, %s\n", lua(blockedField), lua(failuresField))
	fmt.Fprintf(&b, "local PROMOTE_BATCH = %d\n", PromoteBatch)
	fmt.Fprintf(&b, "local FEED_LENGTH = %d\n", FeedLength)
	fmt.Fprintf(&b, "local SPARES = {%s}\n", sparedKinds())
	for _, k := range []struct{ fn, prefix string }{
		{"jkey", jobPrefix}, {"rkey", roundsPrefix}, {"skey", stagesPrefix}, {"lkey", leasesPrefix}, {"tkey", taskPrefix}, {"readykey", readyPrefix}, {"wkey", workerPrefix},
	} {
		fmt.Fprintf(&b, "local function %s(id) return P .. %s .. id end\n", k.fn, lua(k.prefix))
	}
	fmt.Fprintf(&b, "local function qkey(jid, phase) return P .. %s .. jid .. %s .. phase end\n", lua(queuePrefix), lua(queueSeparator))
	return b.String()
}

// sparedKinds lists, as Lua table entries ("[4] = true"), the failure kinds whose
// failure_info does not blame the worker (tasks.FailureOf): their failed attempts do not
// count toward the blocklist. Unknown kinds blame it, as in Go.
func sparedKinds() string {
	var entries []string
	values := pb.FailureKind(0).Descriptor().Values()
	for i := 0; i < values.Len(); i++ {
		if n := values.Get(i).Number(); !tasks.FailureOf(pb.FailureKind(n)).BlamesWorker {
			entries = append(entries, fmt.Sprintf("[%d] = true", n))
		}
	}
	return strings.Join(entries, ", ")
}

// enumLocals declares a Lua local per value of enum ed but 0, named prefix + the value's
// name without trim ("LEASED", "JRUNNING"), and, unless names is empty, a table names of
// the trimmed names by number, for messages.
func enumLocals(b *strings.Builder, ed protoreflect.EnumDescriptor, trim, prefix, names string) {
	var locals, numbers, entries []string
	values := ed.Values()
	for i := 0; i < values.Len(); i++ {
		v := values.Get(i)
		if v.Number() == 0 {
			continue
		}
		name := strings.TrimPrefix(string(v.Name()), trim)
		locals = append(locals, prefix+name)
		numbers = append(numbers, fmt.Sprint(v.Number()))
		entries = append(entries, fmt.Sprintf("[%d] = %s", v.Number(), lua(name)))
	}
	fmt.Fprintf(b, "local %s = %s\n", strings.Join(locals, ", "), strings.Join(numbers, ", "))
	if names != "" {
		fmt.Fprintf(b, "local %s = {%s}\n", names, strings.Join(entries, ", "))
	}
}

// lua quotes s as a Lua string literal; the names quoted here are plain ASCII.
func lua(s string) string {
	if strings.ContainsAny(s, `'\`+"\n") {
		panic("redisstore: key name " + s + " needs escaping")
	}
	return "'" + s + "'"
}
