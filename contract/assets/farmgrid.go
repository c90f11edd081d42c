package assets

import (
	"bufio"
	"bytes"
	"context"
	"encoding/binary"
	"fmt"
	"io"
	"math"

	"photonfarm/contract/rules"
)

// The farm grid file (docs/grid-format.md): a heterogeneous medium's densities on a dense
// voxel grid, in binary.

// FarmGridMagic starts every farm grid file.
const FarmGridMagic = "FARMGRID"

const (
	farmGridVersion = 1
	farmGridHeader  = 48
)

// GridData is a density grid in memory, as the scene generators make it: Nx x Ny x Nz
// densities at the centres of the cells of the box [Min, Max], x fastest, then y, then z.
type GridData struct {
	Nx, Ny, Nz uint32
	Min, Max   [3]float32
	Densities  []float32
}

// EncodeFarmGrid writes g as a farm grid file. It refuses a grid whose densities are not
// Nx x Ny x Nz (a bug of the caller); what the file holds is checked by CheckFarmGrid.
func EncodeFarmGrid(w io.Writer, g *GridData) error {
	if uint64(len(g.Densities)) != uint64(g.Nx)*uint64(g.Ny)*uint64(g.Nz) {
		return fmt.Errorf("assets: %d densities for a grid of %d x %d x %d cells", len(g.Densities), g.Nx, g.Ny, g.Nz)
	}
	bw := bufio.NewWriter(w)
	var head [farmGridHeader]byte
	copy(head[:8], FarmGridMagic)
	binary.LittleEndian.PutUint32(head[8:], farmGridVersion)
	for a, n := range []uint32{g.Nx, g.Ny, g.Nz} {
		binary.LittleEndian.PutUint32(head[12+4*a:], n)
	}
	for a := 0; a < 3; a++ {
		binary.LittleEndian.PutUint32(head[24+4*a:], math.Float32bits(g.Min[a]))
		binary.LittleEndian.PutUint32(head[36+4*a:], math.Float32bits(g.Max[a]))
	}
	bw.Write(head[:])
	if err := binary.Write(bw, binary.LittleEndian, g.Densities); err != nil {
		return err
	}
	return bw.Flush()
}

// IsFarmGrid reports whether a file's first bytes are a farm grid file's magic.
func IsFarmGrid(head []byte) bool { return bytes.HasPrefix(head, []byte(FarmGridMagic)) }

// GridLimits are the limits a grid file is held to: Scene's max_asset_bytes,
// max_grid_cells and max_grid_axis_cells unless a test says otherwise.
type GridLimits struct {
	MaxBytes, MaxCells uint64
	MaxAxisCells       uint32
}

// SceneGridLimits are the contract's limits of a grid file.
func SceneGridLimits() GridLimits {
	return GridLimits{
		MaxBytes:     rules.Scene.GetMaxAssetBytes(),
		MaxCells:     rules.Scene.GetMaxGridCells(),
		MaxAxisCells: rules.Scene.GetMaxGridAxisCells(),
	}
}

// Grid is what checking a farm grid file learnt of it.
type Grid struct {
	Nx, Ny, Nz uint32
	Min, Max   [3]float64
	MaxDensity float64
}

// FarmGridError says where in a farm grid file it is wrong and why.
type FarmGridError struct {
	Offset int64
	Reason string
}

func (e *FarmGridError) Error() string { return fmt.Sprintf("byte %d: %s", e.Offset, e.Reason) }

func (*FarmGridError) refused() {}

func refuseGrid(offset int64, reason string) error {
	return &FarmGridError{Offset: offset, Reason: reason}
}

var axisNames = [3]string{"x", "y", "z"}

// CheckFarmGrid reads the farm grid file open opens, streaming, and checks it against
// docs/grid-format.md and lim, in this order: the header (magic, version, the cell counts
// against the limits, the box finite, within max_magnitude and not empty on any axis),
// then every density (finite, >= 0, within max_magnitude), then that the file ends there.
// It returns the grid's counts, box and largest density, a *FarmGridError naming the
// offset of the first thing wrong, the error of opening or reading the file, or ctx's
// error if ctx ends first.
func CheckFarmGrid(ctx context.Context, open Opener, lim GridLimits) (Grid, error) {
	f, err := open()
	if err != nil {
		return Grid{}, err
	}
	defer f.Close()
	r := &offsetReader{r: bufio.NewReader(&limitedReader{ctx: ctx, r: f, left: lim.MaxBytes}), refuse: refuseGrid}
	var head [farmGridHeader]byte
	if err := r.full(head[:]); err != nil {
		return Grid{}, r.fail(err, fmt.Sprintf("the file ends inside its %d-byte header", farmGridHeader))
	}
	refuse := func(at int64, format string, args ...any) (Grid, error) {
		return Grid{}, refuseGrid(at, fmt.Sprintf(format, args...))
	}
	if !IsFarmGrid(head[:]) {
		return refuse(0, "not a farm grid file (no %q magic)", FarmGridMagic)
	}
	if v := binary.LittleEndian.Uint32(head[8:]); v != farmGridVersion {
		return refuse(8, "version %d, but this farm reads version %d", v, farmGridVersion)
	}
	var g Grid
	counts := [3]*uint32{&g.Nx, &g.Ny, &g.Nz}
	cells := uint64(1)
	for a := range 3 {
		n := binary.LittleEndian.Uint32(head[12+4*a:])
		switch {
		case n == 0:
			return refuse(int64(12+4*a), "the grid has no cells along %s", axisNames[a])
		case n > lim.MaxAxisCells:
			return refuse(int64(12+4*a), "%d cells along %s, more than the %d of one axis", n, axisNames[a], lim.MaxAxisCells)
		}
		*counts[a] = n
		cells *= uint64(n)
	}
	if cells > lim.MaxCells {
		return refuse(12, "%d x %d x %d = %d cells, more than the %d of one grid", g.Nx, g.Ny, g.Nz, cells, lim.MaxCells)
	}
	magnitude := rules.Scene.GetMaxMagnitude()
	for i := range 6 {
		at := 24 + 4*i
		x := float64(math.Float32frombits(binary.LittleEndian.Uint32(head[at:])))
		name := "min." + axisNames[i%3]
		if i >= 3 {
			name = "max." + axisNames[i%3]
		}
		switch {
		case math.IsNaN(x) || math.IsInf(x, 0):
			return refuse(int64(at), "the box's %s is not finite", name)
		case math.Abs(x) > magnitude:
			return refuse(int64(at), "the box's %s %s is out of range: numbers are at most ±%s", name, rules.Number(x), rules.Number(magnitude))
		}
		if i < 3 {
			g.Min[i] = x
		} else {
			g.Max[i-3] = x
		}
	}
	for a := range 3 {
		if !(g.Max[a] > g.Min[a]) {
			return refuse(int64(36+4*a), "the box's max.%s %s is not above its min.%s %s", axisNames[a], rules.Number(g.Max[a]), axisNames[a], rules.Number(g.Min[a]))
		}
	}
	var word [4]byte
	for i := uint64(0); i < cells; i++ {
		at := r.n
		if err := r.full(word[:]); err != nil {
			return Grid{}, r.fail(err, "the file ends inside its densities")
		}
		d := float64(math.Float32frombits(binary.LittleEndian.Uint32(word[:])))
		x, y, z := i%uint64(g.Nx), i/uint64(g.Nx)%uint64(g.Ny), i/uint64(g.Nx)/uint64(g.Ny)
		switch {
		case math.IsNaN(d) || math.IsInf(d, 0):
			return refuse(at, "the density of cell (%d, %d, %d) is not finite", x, y, z)
		case d < 0:
			return refuse(at, "the density of cell (%d, %d, %d) is negative: %s", x, y, z, rules.Number(d))
		case d > magnitude:
			return refuse(at, "the density of cell (%d, %d, %d) %s is out of range: numbers are at most ±%s", x, y, z, rules.Number(d), rules.Number(magnitude))
		}
		g.MaxDensity = math.Max(g.MaxDensity, d)
	}
	if _, err := r.r.ReadByte(); err != io.EOF {
		if err != nil {
			return Grid{}, r.fail(err, "")
		}
		return refuse(r.n, "the file goes on past its last cell")
	}
	return g, nil
}
