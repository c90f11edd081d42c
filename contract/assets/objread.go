package assets

import (
	"bytes"
	"context"
	"strconv"
)

// OBJ is an OBJ file read whole, for import: its vertex data, its triangles grouped by
// the material they were declared under (usemtl), and the MTL files it names.
type OBJ struct {
	Positions [][3]float32
	TexCoords [][2]float32 // u, v as the file has them (v grows upwards)
	Normals   [][3]float32
	// Groups in the order their material first appears; "" for faces before any usemtl.
	Groups   []*OBJGroup
	MtlLibs  []string
	Triangle uint64
}

// OBJGroup is the triangles of one material: three corners each.
type OBJGroup struct {
	Material string
	Corners  []OBJCorner
}

// OBJCorner is a triangle corner: 0-based indices into OBJ's arrays, -1 where the face
// gives none.
type OBJCorner struct {
	Position, TexCoord, Normal int
}

// ReadOBJ checks the OBJ file open opens (CheckOBJ: the same rules and messages) and then
// reads it. Polygons are split into fans of triangles, as the worker splits them.
func ReadOBJ(ctx context.Context, open Opener, lim Limits) (*OBJ, error) {
	if _, err := CheckOBJ(ctx, open, lim); err != nil {
		return nil, err
	}
	out := &OBJ{}
	groups := map[string]*OBJGroup{}
	current := func(name string) *OBJGroup {
		g, ok := groups[name]
		if !ok {
			g = &OBJGroup{Material: name}
			groups[name] = g
			out.Groups = append(out.Groups, g)
		}
		return g
	}
	group := (*OBJGroup)(nil)
	var fields [][]byte
	var corners []OBJCorner
	_, err := scan(ctx, open, lim, func(line []byte) error {
		fields = tokens(fields[:0], line)
		if len(fields) == 0 {
			return nil
		}
		args := fields[1:]
		switch string(fields[0]) {
		case "v":
			out.Positions = append(out.Positions, [3]float32{parseFloat32(args[0]), parseFloat32(args[1]), parseFloat32(args[2])})
		case "vt":
			var uv [2]float32
			uv[0] = parseFloat32(args[0])
			if len(args) > 1 {
				uv[1] = parseFloat32(args[1])
			}
			out.TexCoords = append(out.TexCoords, uv)
		case "vn":
			out.Normals = append(out.Normals, [3]float32{parseFloat32(args[0]), parseFloat32(args[1]), parseFloat32(args[2])})
		case "usemtl":
			group = current(string(bytes.Join(args, []byte(" "))))
		case "mtllib":
			// MTL file names may hold spaces: they are the rest of the line.
			out.MtlLibs = append(out.MtlLibs, string(bytes.Join(args, []byte(" "))))
		case "f":
			if group == nil {
				group = current("")
			}
			corners = corners[:0]
			for _, ref := range args {
				corners = append(corners, out.corner(ref))
			}
			for i := 1; i+1 < len(corners); i++ {
				group.Corners = append(group.Corners, corners[0], corners[i], corners[i+1])
				out.Triangle++
			}
		}
		return nil
	})
	if err != nil {
		return nil, err
	}
	return out, nil
}

// corner resolves a face reference that CheckOBJ accepted (v, v/vt, v//vn, v/vt/vn).
func (o *OBJ) corner(ref []byte) OBJCorner {
	c := OBJCorner{-1, -1, -1}
	parts := bytes.SplitN(ref, []byte("/"), 3)
	counts := [3]int{len(o.Positions), len(o.TexCoords), len(o.Normals)}
	out := [3]*int{&c.Position, &c.TexCoord, &c.Normal}
	for i, p := range parts {
		if len(p) == 0 {
			continue
		}
		idx, _ := integer(p)
		if idx < 0 {
			*out[i] = counts[i] + int(idx)
		} else {
			*out[i] = int(idx) - 1
		}
	}
	return c
}

// parseFloat32 parses a number CheckOBJ accepted.
func parseFloat32(b []byte) float32 {
	v, _ := strconv.ParseFloat(string(b), 32)
	return float32(v)
}
