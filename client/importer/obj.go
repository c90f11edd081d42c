package importer

import (
	"bytes"
	"context"
	"fmt"
	"io"
	"math"
	"path/filepath"

	"photonfarm/contract/assets"
	pb "photonfarm/proto/renderfarm/v1"
)

// importOBJ reads an OBJ file and the MTL files it names: one mesh whose parts are its
// usemtl groups, placed once.
func importOBJ(ctx context.Context, src string, w *writer, opt Options) (*Result, error) {
	lim := assets.SceneLimits()
	files := sourceFS{dir: filepath.Dir(src), limit: int64(lim.MaxBytes)}
	obj, err := assets.ReadOBJ(ctx, func() (io.ReadCloser, error) { return files.Open(filepath.Base(src)) }, lim)
	if err != nil {
		return nil, err
	}
	b := newBuild(src)
	mtl := map[string]*mtlMaterial{}
	for _, lib := range obj.MtlLibs {
		data, err := files.ReadFile(lib)
		if err != nil {
			return nil, fmt.Errorf("mtllib %s: %v", lib, err)
		}
		if err := parseMTL(data, mtl); err != nil {
			return nil, fmt.Errorf("%s: %v", lib, err)
		}
	}
	im := &objImport{build: b, files: files, w: w, mtl: mtl, materials: map[string]string{}, textures: map[string]string{}}
	mesh := &pb.Mesh{Name: b.scene.Name}
	for i, g := range obj.Groups {
		if len(g.Corners) == 0 {
			continue
		}
		data, bx := objMeshData(obj, g)
		material, err := im.material(g.Material)
		if err != nil {
			return nil, err
		}
		path, err := w.mesh(fmt.Sprintf("%s-%d", b.scene.Name, i), data)
		if err != nil {
			return nil, err
		}
		mesh.Parts = append(mesh.Parts, &pb.MeshPart{Path: path, Material: material})
		b.bounds = b.bounds.union(bx)
	}
	b.scene.Meshes = []*pb.Mesh{mesh}
	b.scene.Shapes = []*pb.Shape{{Name: b.scene.Name, Geometry: &pb.Shape_Instance{Instance: &pb.MeshInstance{Mesh: mesh.Name}}}}
	return b.finish(w, opt)
}

// objMeshData makes the farm mesh of one group: a vertex per distinct corner (position,
// texture coordinate, normal), with normals and texture coordinates only if every corner
// has them. OBJ's v grows upwards in the image, the farm's downwards (docs/mesh-format.md).
func objMeshData(obj *assets.OBJ, g *assets.OBJGroup) (*assets.MeshData, box) {
	withUV, withNormals := true, true
	for _, c := range g.Corners {
		withUV = withUV && c.TexCoord >= 0
		withNormals = withNormals && c.Normal >= 0
	}
	m := &assets.MeshData{}
	var bx box
	seen := map[assets.OBJCorner]uint32{}
	for _, c := range g.Corners {
		if !withUV {
			c.TexCoord = -1
		}
		if !withNormals {
			c.Normal = -1
		}
		v, ok := seen[c]
		if !ok {
			v = uint32(len(m.Positions) / 3)
			seen[c] = v
			p := obj.Positions[c.Position]
			m.Positions = append(m.Positions, p[0], p[1], p[2])
			bx = bx.add([3]float64{float64(p[0]), float64(p[1]), float64(p[2])})
			if withUV {
				uv := obj.TexCoords[c.TexCoord]
				m.TexCoords = append(m.TexCoords, uv[0], 1-uv[1])
			}
			if withNormals {
				n := obj.Normals[c.Normal]
				m.Normals = append(m.Normals, n[0], n[1], n[2])
			}
		}
		m.Indices = append(m.Indices, v)
	}
	return m, bx
}

type objImport struct {
	*build
	files sourceFS
	w     *writer
	mtl   map[string]*mtlMaterial
	// The farm's names of the MTL materials and texture files written so far.
	materials, textures map[string]string
}

// material returns the farm name of MTL material name, writing it the first time.
func (o *objImport) material(name string) (string, error) {
	if farm, ok := o.materials[name]; ok {
		return farm, nil
	}
	m, ok := o.mtl[name]
	if !ok {
		if name != "" {
			o.skip("usemtl %s names no material of the MTL files (a grey one is used)", name)
		}
		m = &mtlMaterial{kd: [3]float64{0.8, 0.8, 0.8}, d: 1, ns: 0}
	}
	farm := name
	if farm == "" {
		farm = "obj default"
	}
	farm = truncate(farm)
	out, err := o.convert(name, m)
	if err != nil {
		return "", fmt.Errorf("material %s: %w", name, err)
	}
	out.Name = farm
	o.scene.Materials = append(o.scene.Materials, out)
	o.materials[name] = farm
	return farm, nil
}

// convert maps an MTL material to the farm's (docs/import.md): glass (illum 4, 6, 7 or 9
// with an index of refraction) to Dielectric, anything else to Principled, with the
// roughness a Phong exponent corresponds to.
func (o *objImport) convert(name string, m *mtlMaterial) (*pb.Material, error) {
	switch m.illum {
	case 4, 6, 7, 9:
		if m.ni > 1 {
			return &pb.Material{Kind: &pb.Material_Dielectric{Dielectric: &pb.Dielectric{
				Ior: math.Min(m.ni, 10), Transmittance: color(clamp01(m.tf[0]), clamp01(m.tf[1]), clamp01(m.tf[2]))}}}, nil
		}
	}
	p := &pb.Principled{
		BaseColor:    color(clamp01(m.kd[0]), clamp01(m.kd[1]), clamp01(m.kd[2])),
		Roughness:    m.roughness(),
		Metallic:     clamp01(m.pm),
		Transparency: 1 - clamp01(m.d),
	}
	if m.ke != [3]float64{} {
		p.Emission = color(math.Max(m.ke[0], 0), math.Max(m.ke[1], 0), math.Max(m.ke[2], 0))
		o.emits = true
	}
	var err error
	for _, t := range []struct {
		file string
		ref  **pb.TextureRef
	}{{m.mapKd, &p.BaseColorTexture}, {m.mapKe, &p.EmissionTexture}, {m.bump, &p.NormalTexture}} {
		if t.file == "" {
			continue
		}
		if *t.ref, err = o.texture(t.file); err != nil {
			return nil, err
		}
	}
	if m.mapD != "" && m.mapD != m.mapKd {
		o.skip("material %s: its map_d (only the base colour texture's alpha cuts out)", name)
	}
	if m.mapD != "" {
		p.AlphaMode = pb.AlphaMode_ALPHA_MODE_MASK
	}
	if m.mapKs != "" || m.mapNs != "" {
		o.skip("material %s: its map_Ks and map_Ns (the factors are used)", name)
	}
	return &pb.Material{Kind: &pb.Material_Principled{Principled: p}}, nil
}

// texture returns a reference to the farm texture of an image file an MTL names,
// copying the file the first time.
func (o *objImport) texture(file string) (*pb.TextureRef, error) {
	if name, ok := o.textures[file]; ok {
		return &pb.TextureRef{Texture: name}, nil
	}
	data, err := o.files.ReadFile(file)
	if err != nil {
		return nil, fmt.Errorf("texture %s: %v", file, err)
	}
	t, err := checkImage(data)
	if err != nil {
		return nil, fmt.Errorf("texture %s: %v", file, err)
	}
	stem := filepath.Base(file)
	stem = stem[:len(stem)-len(filepath.Ext(stem))]
	path, err := o.w.file("textures", stem, "."+extensionOf(t.Format), data)
	if err != nil {
		return nil, err
	}
	name := truncate(file)
	o.scene.Textures = append(o.scene.Textures, &pb.Texture{Name: name, Path: path})
	o.textures[file] = name
	return &pb.TextureRef{Texture: name}, nil
}

// mtlMaterial is what an MTL file says of one material.
type mtlMaterial struct {
	kd, ke, tf         [3]float64
	ns, ni, d, pm, pr  float64
	hasPr              bool
	illum              int
	mapKd, mapKe, bump string
	mapKs, mapNs, mapD string
}

// roughness is Pr when the file gives one (the PBR extension of MTL), else the GGX
// roughness whose lobe matches the Phong exponent Ns: Phong's exponent n and a microfacet
// alpha relate as alpha = sqrt(2 / (n + 2)) (Walter et al. 2007), and the farm's
// roughness is sqrt(alpha).
func (m *mtlMaterial) roughness() float64 {
	if m.hasPr {
		return clamp01(m.pr)
	}
	return clamp01(math.Pow(2/(math.Max(m.ns, 0)+2), 0.25))
}

// parseMTL adds the materials of an MTL file to into.
func parseMTL(data []byte, into map[string]*mtlMaterial) error {
	var m *mtlMaterial
	for n, line := range bytes.Split(data, []byte("\n")) {
		f := bytes.Fields(bytes.TrimRight(line, "\r"))
		if len(f) == 0 || f[0][0] == '#' {
			continue
		}
		key, args := string(f[0]), f[1:]
		if key == "newmtl" {
			name := string(bytes.Join(args, []byte(" ")))
			m = &mtlMaterial{d: 1, tf: [3]float64{1, 1, 1}, kd: [3]float64{0.8, 0.8, 0.8}}
			into[name] = m
			continue
		}
		if m == nil {
			return fmt.Errorf("line %d: %s before any newmtl", n+1, key)
		}
		var err error
		switch key {
		case "Kd":
			m.kd, err = rgb(args)
		case "Ke":
			m.ke, err = rgb(args)
		case "Tf":
			m.tf, err = rgb(args)
		case "Ns":
			m.ns, err = one(args)
		case "Ni":
			m.ni, err = one(args)
		case "d":
			m.d, err = one(args)
		case "Tr":
			var tr float64
			tr, err = one(args)
			m.d = 1 - tr
		case "Pm":
			m.pm, err = one(args)
		case "Pr":
			m.pr, err = one(args)
			m.hasPr = true
		case "illum":
			var v float64
			v, err = one(args)
			m.illum = int(v)
		case "map_Kd":
			m.mapKd = mapFile(args)
		case "map_Ke":
			m.mapKe = mapFile(args)
		case "map_Ks":
			m.mapKs = mapFile(args)
		case "map_Ns":
			m.mapNs = mapFile(args)
		case "map_d":
			m.mapD = mapFile(args)
		case "map_bump", "map_Bump", "bump", "norm":
			m.bump = mapFile(args)
		}
		if err != nil {
			return fmt.Errorf("line %d: %s: %v", n+1, key, err)
		}
	}
	return nil
}

func one(args [][]byte) (float64, error) {
	if len(args) < 1 {
		return 0, fmt.Errorf("a number is missing")
	}
	v, err := parseNumber(args[0])
	return v, err
}

func rgb(args [][]byte) ([3]float64, error) {
	var c [3]float64
	if len(args) == 0 {
		return c, fmt.Errorf("a colour is missing")
	}
	for i := range c {
		a := args[min(i, len(args)-1)] // "Kd 0.5" is grey
		v, err := parseNumber(a)
		if err != nil {
			return c, err
		}
		c[i] = v
	}
	return c, nil
}

// mapArgs is how many values each texture map option takes.
var mapArgs = map[string]int{"-bm": 1, "-blendu": 1, "-blendv": 1, "-boost": 1, "-cc": 1, "-clamp": 1,
	"-imfchan": 1, "-texres": 1, "-mm": 2, "-o": 3, "-s": 3, "-t": 3}

// mapFile is the file a map_ statement names after its options (the rest of the line).
func mapFile(args [][]byte) string {
	for len(args) > 0 {
		n, ok := mapArgs[string(args[0])]
		if !ok {
			break
		}
		args = args[1:]
		// -o, -s and -t take up to three numbers.
		for ; n > 0 && len(args) > 1; n-- {
			if _, err := parseNumber(args[0]); err != nil && n < 3 {
				break
			}
			args = args[1:]
		}
	}
	return string(bytes.Join(args, []byte(" ")))
}
