package main

import (
	"fmt"
	"html"
	"io"
	"math"
	"strconv"
	"strings"

	pb "photonfarm/proto/renderfarm/v1"
)

// The error-against-time chart of `farm report -o FILE.svg`: a hand-written SVG (no
// script) with log-log axes, decade grid lines, one marker per round for each error the
// rounds report (the estimated error, and the RMSE against the reference when the job has
// one), a legend, and a tooltip (<title>) on each marker naming which of the two it is.
// Rounds without a given error (round 1 has no estimate) have no marker in that
// series; the table lists every round.

const (
	plotWidth, plotHeight                    = 720, 450
	marginLeft, marginRight                  = 80, 24
	marginTop, marginBottom                  = 52, 64
	plotFont                                 = "system-ui, -apple-system, 'Segoe UI', Helvetica, Arial, sans-serif"
	colorEstimate, colorReference, colorGrid = "#1f77b4", "#d62728", "#e5e5e5"
)

// series is one line of the chart.
type series struct {
	name, color, marker string
	points              []point
}

type point struct {
	round      uint32
	time, err  float64
	photons    uint64
	samplesPer uint64
}

// seriesOf splits the rounds into the estimate and the reference series, keeping only
// points a log axis can show.
func seriesOf(rounds []*pb.RoundReport) []series {
	est := series{name: "estimated error", color: colorEstimate, marker: "circle"}
	ref := series{name: "RMSE against the reference", color: colorReference, marker: "square"}
	for _, r := range rounds {
		p := point{round: r.GetRound(), time: r.GetElapsedSeconds(), photons: r.GetPhotons(), samplesPer: r.GetSamplesPerPixel()}
		if p.time <= 0 {
			continue
		}
		if r.ErrorEstimate != nil && r.GetErrorEstimate() > 0 {
			p.err = r.GetErrorEstimate()
			est.points = append(est.points, p)
		}
		if r.ReferenceRmse != nil && r.GetReferenceRmse() > 0 {
			p.err = r.GetReferenceRmse()
			ref.points = append(ref.points, p)
		}
	}
	var out []series
	for _, s := range []series{est, ref} {
		if len(s.points) > 0 {
			out = append(out, s)
		}
	}
	return out
}

// logAxis maps [lo, hi] (positive, in decades widened to whole ones) onto pixels.
type logAxis struct {
	lo, hi     float64 // log10 of the ends
	from, to   float64 // pixels
	ticks      []float64
	minorTicks []float64
}

func newLogAxis(min, max, from, to float64) logAxis {
	lo, hi := math.Floor(math.Log10(min)), math.Ceil(math.Log10(max))
	if hi <= lo {
		hi = lo + 1
	}
	a := logAxis{lo: lo, hi: hi, from: from, to: to}
	for d := lo; d <= hi; d++ {
		a.ticks = append(a.ticks, math.Pow(10, d))
		if d < hi {
			for _, m := range []float64{2, 5} {
				a.minorTicks = append(a.minorTicks, m*math.Pow(10, d))
			}
		}
	}
	return a
}

func (a logAxis) pos(v float64) float64 {
	return a.from + (math.Log10(v)-a.lo)/(a.hi-a.lo)*(a.to-a.from)
}

// tickLabel writes 0.001, 0.01 ... 1000, and 1e-05 / 1e+06 style beyond.
func tickLabel(v float64) string {
	if v >= 1e-3 && v < 1e5 {
		return strconv.FormatFloat(v, 'f', -1, 64)
	}
	return strconv.FormatFloat(v, 'g', 1, 64)
}

func f1(v float64) string { return strconv.FormatFloat(v, 'f', 1, 64) }

// writePlot writes the chart of rounds as a standalone SVG document.
func writePlot(w io.Writer, title string, rounds []*pb.RoundReport) error {
	ss := seriesOf(rounds)
	var b strings.Builder
	fmt.Fprintf(&b, `<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" font-family="%s" font-size="12">
`, plotWidth, plotHeight, plotWidth, plotHeight, plotFont)
	fmt.Fprintf(&b, "<title>%s</title>\n", html.EscapeString(title))
	fmt.Fprintf(&b, `<rect width="%d" height="%d" fill="#ffffff"/>`+"\n", plotWidth, plotHeight)
	fmt.Fprintf(&b, `<text x="%d" y="28" font-size="16" font-weight="600" fill="#222">%s</text>`+"\n", marginLeft, html.EscapeString(title))

	x0, x1 := float64(marginLeft), float64(plotWidth-marginRight)
	y0, y1 := float64(plotHeight-marginBottom), float64(marginTop)
	if len(ss) == 0 {
		fmt.Fprintf(&b, `<text x="%s" y="%s" text-anchor="middle" fill="#666">no round has reported an error yet</text>`+"\n",
			f1((x0+x1)/2), f1((y0+y1)/2))
		b.WriteString("</svg>\n")
		_, err := io.WriteString(w, b.String())
		return err
	}
	tmin, tmax, emin, emax := math.Inf(1), math.Inf(-1), math.Inf(1), math.Inf(-1)
	for _, s := range ss {
		for _, p := range s.points {
			tmin, tmax = math.Min(tmin, p.time), math.Max(tmax, p.time)
			emin, emax = math.Min(emin, p.err), math.Max(emax, p.err)
		}
	}
	xa, ya := newLogAxis(tmin, tmax, x0, x1), newLogAxis(emin, emax, y0, y1)

	// Grid and ticks.
	b.WriteString(`<g class="grid" stroke-width="1">` + "\n")
	for _, v := range xa.minorTicks {
		fmt.Fprintf(&b, `<line x1="%s" y1="%s" x2="%s" y2="%s" stroke="%s" stroke-dasharray="2 3"/>`+"\n", f1(xa.pos(v)), f1(y0), f1(xa.pos(v)), f1(y1), colorGrid)
	}
	for _, v := range ya.minorTicks {
		fmt.Fprintf(&b, `<line x1="%s" y1="%s" x2="%s" y2="%s" stroke="%s" stroke-dasharray="2 3"/>`+"\n", f1(x0), f1(ya.pos(v)), f1(x1), f1(ya.pos(v)), colorGrid)
	}
	for _, v := range xa.ticks {
		x := f1(xa.pos(v))
		fmt.Fprintf(&b, `<line x1="%s" y1="%s" x2="%s" y2="%s" stroke="%s"/>`+"\n", x, f1(y0), x, f1(y1), colorGrid)
		fmt.Fprintf(&b, `<text x="%s" y="%s" text-anchor="middle" fill="#444">%s</text>`+"\n", x, f1(y0+18), tickLabel(v))
	}
	for _, v := range ya.ticks {
		y := f1(ya.pos(v))
		fmt.Fprintf(&b, `<line x1="%s" y1="%s" x2="%s" y2="%s" stroke="%s"/>`+"\n", f1(x0), y, f1(x1), y, colorGrid)
		fmt.Fprintf(&b, `<text x="%s" y="%s" text-anchor="end" dominant-baseline="middle" fill="#444">%s</text>`+"\n", f1(x0-8), y, tickLabel(v))
	}
	b.WriteString("</g>\n")
	fmt.Fprintf(&b, `<rect x="%s" y="%s" width="%s" height="%s" fill="none" stroke="#888"/>`+"\n", f1(x0), f1(y1), f1(x1-x0), f1(y0-y1))

	// Axis titles.
	fmt.Fprintf(&b, `<text x="%s" y="%d" text-anchor="middle" font-size="13" fill="#222">elapsed time since the job was submitted (s, log scale)</text>`+"\n",
		f1((x0+x1)/2), plotHeight-18)
	fmt.Fprintf(&b, `<text transform="translate(20 %s) rotate(-90)" text-anchor="middle" font-size="13" fill="#222">RMSE of the image (log scale)</text>`+"\n",
		f1((y0+y1)/2))

	// Series: a line through the rounds and one marker each.
	for _, s := range ss {
		fmt.Fprintf(&b, `<g class="series" data-name="%s" fill="%s" stroke="%s">`+"\n", html.EscapeString(s.name), s.color, s.color)
		var path []string
		for _, p := range s.points {
			path = append(path, f1(xa.pos(p.time))+","+f1(ya.pos(p.err)))
		}
		fmt.Fprintf(&b, `<polyline points="%s" fill="none" stroke-width="2"/>`+"\n", strings.Join(path, " "))
		for _, p := range s.points {
			x, y := xa.pos(p.time), ya.pos(p.err)
			tip := fmt.Sprintf("round %d: %.3g s, %s %.4g, %d photon paths, %d samples per pixel", p.round, p.time, s.name, p.err, p.photons, p.samplesPer)
			if s.marker == "square" {
				fmt.Fprintf(&b, `<rect class="point" data-round="%d" x="%s" y="%s" width="8" height="8"><title>%s</title></rect>`+"\n",
					p.round, f1(x-4), f1(y-4), html.EscapeString(tip))
			} else {
				fmt.Fprintf(&b, `<circle class="point" data-round="%d" cx="%s" cy="%s" r="4.5"><title>%s</title></circle>`+"\n",
					p.round, f1(x), f1(y), html.EscapeString(tip))
			}
		}
		b.WriteString("</g>\n")
	}

	// Legend, top right inside the plot.
	lx, ly := x1-290, y1+12
	fmt.Fprintf(&b, `<g class="legend"><rect x="%s" y="%s" width="280" height="%d" fill="#ffffff" fill-opacity="0.9" stroke="#ccc"/>`+"\n",
		f1(lx), f1(ly), 10+20*len(ss))
	for i, s := range ss {
		y := ly + 18 + 20*float64(i)
		fmt.Fprintf(&b, `<line x1="%s" y1="%s" x2="%s" y2="%s" stroke="%s" stroke-width="2"/>`+"\n", f1(lx+10), f1(y-4), f1(lx+34), f1(y-4), s.color)
		fmt.Fprintf(&b, `<text x="%s" y="%s" fill="#222">%s</text>`+"\n", f1(lx+42), f1(y), html.EscapeString(s.name))
	}
	b.WriteString("</g>\n</svg>\n")
	_, err := io.WriteString(w, b.String())
	return err
}
