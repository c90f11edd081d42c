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

// The farm mesh file (docs/mesh-format.md): triangles in binary, with optional normals,
// texture coordinates and tangents.

// FarmMeshMagic starts every farm mesh file.
const FarmMeshMagic = "FARMMESH"

const (
	farmMeshVersion = 1
	farmMeshHeader  = 32
	// Flags of the header.
	HasNormals   = 1 << 0
	HasTexCoords = 1 << 1
	HasTangents  = 1 << 2
	knownFlags   = HasNormals | HasTexCoords | HasTangents
)

// MeshData is a mesh in memory, as farm import makes it. Normals, TexCoords and Tangents
// are empty or have an entry per position (3, 2 and 4 floats each).
type MeshData struct {
	Positions []float32 // x, y, z per vertex
	Normals   []float32
	TexCoords []float32 // u, v per vertex
	Tangents  []float32 // x, y, z, w per vertex
	Indices   []uint32  // a, b, c per triangle
}

func (m *MeshData) flags() uint32 {
	var f uint32
	if len(m.Normals) > 0 {
		f |= HasNormals
	}
	if len(m.TexCoords) > 0 {
		f |= HasTexCoords
	}
	if len(m.Tangents) > 0 {
		f |= HasTangents
	}
	return f
}

// EncodeFarmMesh writes m as a farm mesh file. It refuses a mesh whose arrays disagree in
// length (a bug of the caller); what the file holds is checked by CheckFarmMesh.
func EncodeFarmMesh(w io.Writer, m *MeshData) error {
	v := len(m.Positions) / 3
	if len(m.Positions)%3 != 0 || len(m.Indices)%3 != 0 ||
		(len(m.Normals) != 0 && len(m.Normals) != 3*v) ||
		(len(m.TexCoords) != 0 && len(m.TexCoords) != 2*v) ||
		(len(m.Tangents) != 0 && len(m.Tangents) != 4*v) {
		return fmt.Errorf("assets: mesh arrays of %d positions, %d normals, %d texture coordinates, %d tangents and %d indices do not fit together",
			len(m.Positions), len(m.Normals), len(m.TexCoords), len(m.Tangents), len(m.Indices))
	}
	bw := bufio.NewWriter(w)
	var head [farmMeshHeader]byte
	copy(head[:8], FarmMeshMagic)
	binary.LittleEndian.PutUint32(head[8:], farmMeshVersion)
	binary.LittleEndian.PutUint32(head[12:], m.flags())
	binary.LittleEndian.PutUint64(head[16:], uint64(v))
	binary.LittleEndian.PutUint64(head[24:], uint64(len(m.Indices)/3))
	bw.Write(head[:])
	for _, section := range [][]float32{m.Positions, m.Normals, m.TexCoords, m.Tangents} {
		if err := binary.Write(bw, binary.LittleEndian, section); err != nil {
			return err
		}
	}
	if err := binary.Write(bw, binary.LittleEndian, m.Indices); err != nil {
		return err
	}
	return bw.Flush()
}

// IsFarmMesh reports whether a file's first bytes are a farm mesh file's magic.
func IsFarmMesh(head []byte) bool { return bytes.HasPrefix(head, []byte(FarmMeshMagic)) }

// FarmMeshError says where in a farm mesh file it is wrong and why.
type FarmMeshError struct {
	Offset int64
	Reason string
}

func (e *FarmMeshError) Error() string { return fmt.Sprintf("byte %d: %s", e.Offset, e.Reason) }

func (*FarmMeshError) refused() {}

// CheckFarmMesh reads the farm mesh file open opens, streaming, and checks it against
// docs/mesh-format.md and lim. It returns the mesh's counts and bounds, a *FarmMeshError
// naming the offset of the first thing wrong, the error of opening or reading the file,
// or ctx's error if ctx ends first.
func CheckFarmMesh(ctx context.Context, open Opener, lim Limits) (Mesh, error) {
	f, err := open()
	if err != nil {
		return Mesh{}, err
	}
	defer f.Close()
	r := &offsetReader{r: bufio.NewReader(&limitedReader{ctx: ctx, r: f, left: lim.MaxBytes}), refuse: refuseMesh}
	var head [farmMeshHeader]byte
	if err := r.full(head[:]); err != nil {
		return Mesh{}, r.fail(err, "the file ends inside its 32-byte header")
	}
	refuse := func(at int64, format string, args ...any) (Mesh, error) {
		return Mesh{}, &FarmMeshError{Offset: at, Reason: fmt.Sprintf(format, args...)}
	}
	if !IsFarmMesh(head[:]) {
		return refuse(0, "not a farm mesh file (no %q magic)", FarmMeshMagic)
	}
	if v := binary.LittleEndian.Uint32(head[8:]); v != farmMeshVersion {
		return refuse(8, "version %d, but this farm reads version %d", v, farmMeshVersion)
	}
	flags := binary.LittleEndian.Uint32(head[12:])
	if flags&^knownFlags != 0 {
		return refuse(12, "unknown flags 0x%x", flags&^knownFlags)
	}
	nv, nt := binary.LittleEndian.Uint64(head[16:]), binary.LittleEndian.Uint64(head[24:])
	switch {
	case nv == 0:
		return refuse(16, "the mesh has no vertices")
	case nv > lim.MaxVertices:
		return refuse(16, "%d vertices, more than the %d of one mesh", nv, lim.MaxVertices)
	case nt == 0:
		return refuse(24, "the mesh has no triangles")
	case nt > lim.MaxTriangles:
		return refuse(24, "%d triangles, more than the %d of one mesh", nt, lim.MaxTriangles)
	}
	perVertex := uint64(12)
	for _, s := range []struct {
		flag  uint32
		bytes uint64
	}{{HasNormals, 12}, {HasTexCoords, 8}, {HasTangents, 16}} {
		if flags&s.flag != 0 {
			perVertex += s.bytes
		}
	}
	if size := farmMeshHeader + nv*perVertex + 12*nt; size > lim.MaxBytes {
		return refuse(16, "the header implies %d bytes, more than the %d of one asset", size, lim.MaxBytes)
	}
	c := farmMeshChecker{r: r}
	if err := c.floats(3*nv, func(i uint64, x float32) error {
		if m := rules.Scene.GetMaxMagnitude(); math.Abs(float64(x)) > m {
			return fmt.Errorf("position %d's coordinate %s is out of range: numbers are at most ±%s", i/3, rules.Number(float64(x)), rules.Number(m))
		}
		c.extend(i, x)
		return nil
	}, "position"); err != nil {
		return Mesh{}, err
	}
	for _, s := range []struct {
		flag  uint32
		n     uint64
		name  string
		check func(i uint64, x float32) error
	}{
		{HasNormals, 3, "normal", nil},
		{HasTexCoords, 2, "texture coordinate", nil},
		{HasTangents, 4, "tangent", func(i uint64, x float32) error {
			if i%4 == 3 && x != 1 && x != -1 {
				return fmt.Errorf("tangent %d's w is %s, not 1 or -1", i/4, rules.Number(float64(x)))
			}
			return nil
		}},
	} {
		if flags&s.flag != 0 {
			if err := c.floats(s.n*nv, s.check, s.name); err != nil {
				return Mesh{}, err
			}
		}
	}
	var word [4]byte
	for i := uint64(0); i < 3*nt; i++ {
		at := r.n
		if err := r.full(word[:]); err != nil {
			return Mesh{}, r.fail(err, "the file ends before its last triangle")
		}
		if idx := binary.LittleEndian.Uint32(word[:]); uint64(idx) >= nv {
			return refuse(at, "triangle %d refers to vertex %d but the mesh has %d vertices", i/3, idx, nv)
		}
	}
	if _, err := r.r.ReadByte(); err != io.EOF {
		if err != nil {
			return Mesh{}, r.fail(err, "")
		}
		return refuse(r.n, "the file goes on past its last triangle")
	}
	c.mesh.Vertices, c.mesh.Triangles = nv, nt
	return c.mesh, nil
}

// farmMeshChecker reads the float sections of a farm mesh file.
type farmMeshChecker struct {
	r    *offsetReader
	mesh Mesh
}

// floats reads n floats, refusing one that is not finite or that check refuses.
func (c *farmMeshChecker) floats(n uint64, check func(i uint64, x float32) error, name string) error {
	var word [4]byte
	for i := uint64(0); i < n; i++ {
		at := c.r.n
		if err := c.r.full(word[:]); err != nil {
			return c.r.fail(err, "the file ends inside its "+name+"s")
		}
		x := math.Float32frombits(binary.LittleEndian.Uint32(word[:]))
		if math.IsNaN(float64(x)) || math.IsInf(float64(x), 0) {
			return &FarmMeshError{Offset: at, Reason: fmt.Sprintf("%s %d is not finite", name, i)}
		}
		if check != nil {
			if err := check(i, x); err != nil {
				return &FarmMeshError{Offset: at, Reason: err.Error()}
			}
		}
	}
	return nil
}

// extend grows the bounds by coordinate i%3 of vertex i/3.
func (c *farmMeshChecker) extend(i uint64, x float32) {
	k := i % 3
	if i < 3 {
		c.mesh.Min[k], c.mesh.Max[k] = float64(x), float64(x)
	}
	c.mesh.Min[k] = math.Min(c.mesh.Min[k], float64(x))
	c.mesh.Max[k] = math.Max(c.mesh.Max[k], float64(x))
}

func refuseMesh(offset int64, reason string) error {
	return &FarmMeshError{Offset: offset, Reason: reason}
}

// offsetReader counts the bytes read; refuse makes the refusal of the file's format (a
// *FarmMeshError, a *FarmGridError) at an offset.
type offsetReader struct {
	r      *bufio.Reader
	n      int64
	refuse func(offset int64, reason string) error
}

func (o *offsetReader) full(p []byte) error {
	k, err := io.ReadFull(o.r, p)
	o.n += int64(k)
	return err
}

// fail turns a read error into the answer: a file that ends early is refused with
// reason at the offset reached, a file past the size limit as such; other errors (ctx,
// I/O) pass through.
func (o *offsetReader) fail(err error, reason string) error {
	switch {
	case err == io.EOF || err == io.ErrUnexpectedEOF:
		return o.refuse(o.n, reason)
	case err == errTooLarge:
		return o.refuse(o.n, "the file is larger than the limit of one asset")
	}
	return err
}

// CheckMesh checks a mesh file of either kind a scene may name: a farm mesh file if it
// starts with FarmMeshMagic, else an OBJ file.
func CheckMesh(ctx context.Context, open Opener, lim Limits) (Mesh, error) {
	f, err := open()
	if err != nil {
		return Mesh{}, err
	}
	head := make([]byte, len(FarmMeshMagic))
	n, err := io.ReadFull(f, head)
	f.Close()
	if err != nil && err != io.EOF && err != io.ErrUnexpectedEOF {
		return Mesh{}, err
	}
	if IsFarmMesh(head[:n]) {
		return CheckFarmMesh(ctx, open, lim)
	}
	return CheckOBJ(ctx, open, lim)
}
