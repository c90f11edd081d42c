package main

import (
	"cmp"
	"context"
	"fmt"
	"io"
	"os"
	"path/filepath"
	"text/tabwriter"

	"photonfarm/client"
	"photonfarm/contract/rules"
	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
)

var reportVerb = &verb{
	name:    "report",
	args:    "JOB [-o PLOT.svg] [--coordinator ADDR]",
	summary: "print a job's error against run time, round by round; -o writes an SVG plot",
	run:     runReport,
}

func runReport(ctx context.Context, e *env, args []string) error {
	fs := newFlags("report", e)
	out := fs.String("o", "", "also write the error-against-time plot (SVG) to this file")
	return withClient(fs, e, args, 1, 1, func(c *client.Client, pos []string) error {
		job, err := c.GetJob(ctx, pos[0])
		if err != nil {
			return err
		}
		printReport(e.stdout, job)
		if *out == "" {
			return nil
		}
		if err := writePlotFile(*out, job); err != nil {
			return err
		}
		fmt.Fprintf(e.stdout, "plot written to %s\n", *out)
		return nil
	})
}

// printReport writes the job's rounds as a table: the estimated error with its 95%
// interval and the part of it that is the photon estimates' bias (docs/error-estimate.md),
// then the RMSE against the reference with a column for each light layer any round
// measured.
func printReport(w io.Writer, job *pb.Job) {
	name := job.GetDisplayName()
	if name == "" {
		name = job.GetId()
	}
	fmt.Fprintf(w, "job %s (%s): %s, %d rounds\n", printable(job.GetId()), printable(name), tasks.JobStateName(job.GetState()), len(job.GetRounds()))
	var layers []string
	for _, l := range rules.Keys(&pb.RoundMetrics{}, "layer_reference_rmse") {
		for _, r := range job.GetRounds() {
			if _, ok := r.GetLayerReferenceRmse()[l]; ok {
				layers = append(layers, l)
				break
			}
		}
	}
	tw := tabwriter.NewWriter(w, 0, 4, 2, ' ', tabwriter.AlignRight)
	fmt.Fprint(tw, "round\tseconds\tphotons\tsamples/px\testimated error\t95% interval\tof it bias\treference RMSE\t")
	for _, l := range layers {
		fmt.Fprintf(tw, "%s RMSE\t", l)
	}
	fmt.Fprintln(tw)
	for _, r := range job.GetRounds() {
		fmt.Fprintf(tw, "%d\t%.2f\t%s\t%d\t%s\t%s\t%s\t%s\t", r.GetRound(), r.GetElapsedSeconds(), client.FormatCount(r.GetPhotons()),
			r.GetSamplesPerPixel(), client.FormatMetric(r.ErrorEstimate), client.FormatInterval(r.ErrorEstimateLow, r.ErrorEstimateHigh),
			client.FormatMetric(r.ErrorEstimateBias), client.FormatMetric(r.ReferenceRmse))
		for _, l := range layers {
			v, ok := r.GetLayerReferenceRmse()[l]
			if !ok {
				fmt.Fprint(tw, "-\t")
				continue
			}
			fmt.Fprintf(tw, "%s\t", client.FormatMetric(&v))
		}
		fmt.Fprintln(tw)
	}
	tw.Flush()
	printSpread(w, job.GetRounds())
}

// printSpread says where the last round that reports it left the camera samples: the
// EXR layer that maps them, their range over pixels and the share the tenth of the pixels
// with the largest estimated error drew (a tenth when they are spread evenly).
func printSpread(w io.Writer, rounds []*pb.RoundReport) {
	var last *pb.RoundReport
	for _, r := range rounds {
		if r.GetSamples() != nil {
			last = r
		}
	}
	if last == nil {
		return
	}
	sp := last.GetSamples()
	fmt.Fprintf(w, "samples after round %d (layer %s of the EXR): %d to %d a pixel, mean %.2f", last.GetRound(),
		printable(sp.GetLayer()), sp.GetMin(), sp.GetMax(), sp.GetMean())
	if sp.TopErrorDecileShare != nil {
		fmt.Fprintf(w, "; the 10%% of pixels with the largest estimated error drew %.1f%% of them", 100*sp.GetTopErrorDecileShare())
	}
	fmt.Fprintln(w)
}

// writePlotFile writes the plot through a temporary file renamed into place.
func writePlotFile(path string, job *pb.Job) error {
	tmp, err := os.CreateTemp(filepath.Dir(path), ".farm-report-*.svg")
	if err != nil {
		return err
	}
	defer os.Remove(tmp.Name())
	title := fmt.Sprintf("%s: error against time", cmp.Or(job.GetDisplayName(), job.GetId()))
	if err := writePlot(tmp, title, job.GetRounds()); err != nil {
		tmp.Close()
		return err
	}
	if err := tmp.Close(); err != nil {
		return err
	}
	if err := os.Chmod(tmp.Name(), 0o644); err != nil {
		return err
	}
	return os.Rename(tmp.Name(), path)
}
