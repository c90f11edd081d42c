package main

import (
	"bytes"
	"fmt"
	"math"

	"photonfarm/contract/assets"
	"photonfarm/contract/assets/assetstest"
	"photonfarm/contract/rules"
	"photonfarm/tests/vectors/vectorfiles"
)

// gridCase is one farm grid vector (the fields of vectorfiles.BinaryCase).
type gridCase vectorfiles.BinaryCase

// Offsets of the header's fields and of the densities.
const (
	counts    = 12
	box       = 24
	densities = 48
)

// cases lists the farm grid vectors.
func cases() []gridCase {
	good := assetstest.EncodedGrid(assetstest.RampGrid())
	one := assetstest.EncodedGrid(&assets.GridData{Nx: 1, Ny: 1, Nz: 1, Min: [3]float32{0, 0, 0}, Max: [3]float32{1e-3, 1e-3, 1e-3}, Densities: []float32{7}})
	nan, inf := float32(math.NaN()), float32(math.Inf(1))
	maxAxis, maxCells := rules.Scene.GetMaxGridAxisCells(), rules.Scene.GetMaxGridCells()
	// Every axis within its limit, their product past the grid's.
	tooMany := vectorfiles.Put32(vectorfiles.Put32(vectorfiles.Put32(good, counts, maxAxis), counts+4, maxAxis), counts+8, uint32(maxCells/uint64(maxAxis)/uint64(maxAxis)+1))
	cells := uint64(maxAxis) * uint64(maxAxis) * (maxCells/uint64(maxAxis)/uint64(maxAxis) + 1)
	return []gridCase{
		{"accept-ramp", good, 0, ""},
		{"accept-one-cell", one, 0, ""},
		{"accept-density-at-max-magnitude", vectorfiles.Float32(good, densities+4, 1e12), 0, ""},
		{"accept-negative-zero-density", vectorfiles.Float32(good, densities+8, float32(math.Copysign(0, -1))), 0, ""},
		{"accept-box-at-max-magnitude", vectorfiles.Float32(vectorfiles.Float32(good, box, -1e12), box+12, 1e12), 0, ""},

		{"refuse-short-header", good[:30], 30, "the file ends inside its 48-byte header"},
		{"refuse-no-magic", append([]byte("FARMMESH"), good[8:]...), 0, `not a farm grid file (no "FARMGRID" magic)`},
		{"refuse-version-2", vectorfiles.Put32(good, 8, 2), 8, "version 2, but this farm reads version 1"},
		{"refuse-no-cells-along-y", vectorfiles.Put32(good, counts+4, 0), counts + 4, "the grid has no cells along y"},
		{"refuse-too-many-cells-along-z", vectorfiles.Put32(good, counts+8, maxAxis+1), counts + 8, fmt.Sprintf("%d cells along z, more than the %d of one axis", maxAxis+1, maxAxis)},
		{"refuse-too-many-cells", tooMany, counts, fmt.Sprintf("= %d cells, more than the %d of one grid", cells, maxCells)},
		{"refuse-nan-box", vectorfiles.Float32(good, box, nan), box, "the box's min.x is not finite"},
		{"refuse-infinite-box", vectorfiles.Float32(good, box+20, inf), box + 20, "the box's max.z is not finite"},
		{"refuse-box-out-of-range", vectorfiles.Float32(good, box+16, 2e12), box + 16, "the box's max.y 1.999999991808e+12 is out of range: numbers are at most ±1e+12"},
		{"refuse-empty-box", vectorfiles.Float32(good, box+16, 0), box + 16, "the box's max.y 0 is not above its min.y 0"},
		{"refuse-inverted-box", vectorfiles.Float32(good, box+12, -2), box + 12, "the box's max.x -2 is not above its min.x -1"},
		{"refuse-nan-density", vectorfiles.Float32(good, densities+4*5, nan), densities + 4*5, "the density of cell (2, 1, 0) is not finite"},
		{"refuse-infinite-density", vectorfiles.Float32(good, densities+4*11, inf), densities + 4*11, "the density of cell (2, 1, 1) is not finite"},
		{"refuse-negative-density", vectorfiles.Float32(good, densities+4*6, -0.5), densities + 4*6, "the density of cell (0, 0, 1) is negative: -0.5"},
		{"refuse-density-out-of-range", vectorfiles.Float32(good, densities, 1e13), densities, "the density of cell (0, 0, 0) 9.999999827968e+12 is out of range: numbers are at most ±1e+12"},
		{"refuse-file-cut-in-its-densities", good[:len(good)-2], int64(len(good) - 2), "the file ends inside its densities"},
		{"refuse-trailing-bytes", append(bytes.Clone(good), 0), int64(len(good)), "the file goes on past its last cell"},
	}
}
