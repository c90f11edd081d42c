package main

import (
	"fmt"
	"io"
	"strings"
	"sync"
	"time"

	"photonfarm/client"
	"photonfarm/contract/tasks"
	"photonfarm/coordinator/planner"
	pb "photonfarm/proto/renderfarm/v1"
)

// progress shows a job's progress as one fraction for the whole job, its rounds and the
// phases of each folded together (jobFraction), with the round and the phase running
// named beside it: on a terminal, one line redrawn in place,
//
//	round 3/6 Render tiles 2/4 [#########---------------]  21/64 tiles   38%  elapsed 0:04  ETA 0:07
//
// and elsewhere (a log, a pipe) a plain line at once when a phase begins and otherwise at
// most every plainEvery, when something changed:
//
//	job 7: 38%, round 3/6 Render tiles 21/64 tiles, elapsed 4s, ETA 7s
//	job 7: round 6/6 succeeded (emit 4/4, build 1/1, render 64/64, composite 1/1), took 11.2s
type progress struct {
	w   io.Writer
	tty bool
	now func() time.Time

	mu         sync.Mutex
	job        *pb.Job
	frac       *jobFraction
	began      time.Time // when we started watching
	lastPlain  time.Time
	plainText  string // last plain line printed, elapsed and ETA left out
	plainPhase string // the round and phase it named
	width      int    // of the last terminal line drawn
}

const (
	barWidth   = 24
	redrawTTY  = 200 * time.Millisecond
	plainEvery = 2 * time.Second
)

// newProgress shows the progress of a job of rounds planned rounds (0: not known) on w.
func newProgress(w io.Writer, tty bool, now func() time.Time, rounds int) *progress {
	return &progress{w: w, tty: tty, now: now, began: now(), frac: newJobFraction(rounds)}
}

// start begins periodic redrawing; the returned func stops it and prints the job's final
// state (job may be nil if watching failed).
func (p *progress) start() (stop func(job *pb.Job)) {
	done := make(chan struct{})
	var wg sync.WaitGroup
	wg.Add(1)
	go func() {
		defer wg.Done()
		tick := time.NewTicker(redrawTTY)
		defer tick.Stop()
		for {
			select {
			case <-done:
				return
			case <-tick.C:
				p.mu.Lock()
				p.draw(false)
				p.mu.Unlock()
			}
		}
	}()
	return func(job *pb.Job) {
		close(done)
		wg.Wait()
		p.mu.Lock()
		defer p.mu.Unlock()
		if job != nil {
			p.observe(job, p.now())
		}
		p.draw(true)
		if p.tty && p.width > 0 {
			fmt.Fprintln(p.w)
		}
	}
}

// update records the job as it stood at time at (the event's; zero: now).
func (p *progress) update(job *pb.Job, at time.Time) {
	if job == nil {
		return
	}
	p.mu.Lock()
	defer p.mu.Unlock()
	if at.IsZero() {
		at = p.now()
	}
	p.observe(job, at)
	p.draw(false)
}

func (p *progress) observe(job *pb.Job, at time.Time) {
	p.job = job
	p.frac.observe(job, at)
}

// current returns the phase to show and its tasks done and total: the first phase not
// complete, or the last one.
func current(job *pb.Job) (name string, done, total uint32) {
	name, done, total, _ = currentAt(job)
	return name, done, total
}

// currentAt is current with the phase's position (from 1) among the job's phases.
func currentAt(job *pb.Job) (name string, done, total uint32, at int) {
	phases := job.GetPhases()
	if len(phases) == 0 {
		return tasks.JobStateName(job.GetState()), 0, 0, 0
	}
	at = len(phases) - 1
	for i, x := range phases {
		if x.GetTasksSucceeded() < x.GetTasksTotal() {
			at = i
			break
		}
	}
	ph := phases[at]
	return tasks.Label(ph.GetPhase()), ph.GetTasksSucceeded(), ph.GetTasksTotal(), at + 1
}

// phaseOf returns the progress of phase p in job, if the job has that phase.
func phaseOf(job *pb.Job, p pb.Phase) (*pb.PhaseProgress, bool) {
	for _, ph := range job.GetPhases() {
		if ph.GetPhase() == p {
			return ph, true
		}
	}
	return nil, false
}

// roundLabel is "round 3/6 (error 0.012) " for a job that runs progressive rounds
// (without "/6" if the rounds planned are not known), "" for one that does not: the round
// running (or the last one, once the job has ended) and the error of the image so far.
func (p *progress) roundLabel() string {
	job := p.job
	if p.frac.rounds == 1 || !progressive(job) {
		return ""
	}
	rounds := job.GetRounds()
	n := len(rounds)
	if !client.JobEnded(job.GetState()) {
		n++
	}
	label := fmt.Sprintf("round %d", n)
	if p.frac.rounds > 1 {
		label += fmt.Sprintf("/%d", p.frac.rounds)
	}
	if len(rounds) > 0 {
		if name, e, ok := client.RoundError(rounds[len(rounds)-1]); ok {
			label += fmt.Sprintf(" (%s %.3g)", name, e)
		}
	}
	return label + " "
}

// progressive reports whether the job's plan runs progressive rounds.
func progressive(job *pb.Job) bool {
	for _, ps := range job.GetPlan().GetPasses() {
		if ps.GetName() == planner.PassRounds && ps.GetEnabled() {
			return true
		}
	}
	return false
}

// unit names what the tasks of the phase labelled label are.
func unit(label string) string {
	switch label {
	case tasks.Label(pb.Phase_PHASE_EMIT):
		return "shards"
	case tasks.Label(pb.Phase_PHASE_RENDER):
		return "tiles"
	}
	return "tasks"
}

// elapsed is the time since the job was created (or since watching began, if the job
// has no creation time or the clocks disagree); for an ended job, its run time.
func (p *progress) elapsed() time.Duration {
	now := p.now()
	start := p.began
	if t := p.job.GetCreateTime(); t != nil && t.AsTime().Before(now) {
		start = t.AsTime()
	}
	if t := p.job.GetEndTime(); t != nil && client.JobEnded(p.job.GetState()) && t.AsTime().After(start) {
		return t.AsTime().Sub(start)
	}
	return now.Sub(start)
}

// eta is the job's time left; ok is false while there is nothing to go on.
func (p *progress) eta() (time.Duration, bool) { return p.frac.eta(p.elapsed()) }

func clock(d time.Duration) string {
	s := int(d.Round(time.Second) / time.Second)
	if s >= 3600 {
		return fmt.Sprintf("%d:%02d:%02d", s/3600, s/60%60, s%60)
	}
	return fmt.Sprintf("%d:%02d", s/60, s%60)
}

func percent(frac float64) int { return int(100 * frac) }

// draw prints the progress; final forces the plain line out.
func (p *progress) draw(final bool) {
	if p.job == nil {
		return
	}
	if p.tty {
		p.drawTTY(final)
	} else {
		p.drawPlain(final)
	}
}

func (p *progress) drawTTY(final bool) {
	phase, done, total, at := currentAt(p.job)
	state := p.job.GetState()
	if ph, ok := phaseOf(p.job, pb.Phase_PHASE_RENDER); ok && state == pb.JobState_JOB_STATE_SUCCEEDED {
		// Done: show the tiles rendered, not the one composite task.
		phase, done, total = tasks.Label(ph.GetPhase()), ph.GetTasksSucceeded(), ph.GetTasksTotal()
	}
	name := phase
	if n := len(p.job.GetPhases()); n > 0 {
		name = fmt.Sprintf("%s %d/%d", phase, at, n)
	}
	switch {
	case state == pb.JobState_JOB_STATE_QUEUED:
		name = "queued"
	case client.JobEnded(state):
		name = tasks.JobStateName(state)
	}
	name = p.roundLabel() + name
	var b strings.Builder
	filled := int(barWidth * p.frac.shown)
	fmt.Fprintf(&b, "%-14s [%s%s] %4d/%-4d %-6s %3d%%  elapsed %s", name,
		strings.Repeat("#", filled), strings.Repeat("-", barWidth-filled),
		done, total, unit(phase), percent(p.frac.shown), clock(p.elapsed()))
	if !client.JobEnded(state) {
		if eta, ok := p.eta(); ok {
			fmt.Fprintf(&b, "  ETA %s", clock(eta))
		} else {
			b.WriteString("  ETA --:--")
		}
	}
	line := b.String()
	pad := ""
	if n := len(line); n < p.width {
		pad = strings.Repeat(" ", p.width-n)
	}
	p.width = len(line)
	fmt.Fprintf(p.w, "\r%s%s", line, pad)
	_ = final
}

func (p *progress) drawPlain(final bool) {
	job := p.job
	id := printable(job.GetId())
	phase, done, total := current(job)
	name := p.roundLabel() + phase
	var text string
	switch state := job.GetState(); {
	case client.JobEnded(state):
		text = fmt.Sprintf("job %s: %s%s", id, p.roundLabel(), tasks.JobStateName(state))
		if s := phaseSummary(job); s != "" {
			text += " (" + s + ")"
		}
	case state == pb.JobState_JOB_STATE_QUEUED:
		text = fmt.Sprintf("job %s: queued", id)
	default:
		text = fmt.Sprintf("job %s: %d%%, %s %d/%d %s", id, percent(p.frac.shown), name, done, total, unit(phase))
	}
	now := p.now()
	changed := text != p.plainText
	if !changed || (!final && name == p.plainPhase && now.Sub(p.lastPlain) < plainEvery) {
		return
	}
	p.plainText, p.plainPhase, p.lastPlain = text, name, now
	if client.JobEnded(job.GetState()) {
		fmt.Fprintf(p.w, "%s, took %s\n", text, p.elapsed().Round(time.Millisecond))
		return
	}
	line := fmt.Sprintf("%s, elapsed %s", text, p.elapsed().Round(time.Second))
	if eta, ok := p.eta(); ok {
		line += fmt.Sprintf(", ETA %s", eta.Round(time.Second))
	}
	fmt.Fprintln(p.w, line)
}
