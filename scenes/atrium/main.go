// Package atrium writes the project's demonstration scene of real-asset rendering
// (issue 13): a Sponza-like atrium as a glTF 2.0 binary, with an equirectangular sky to
// light it.
//
//	go run ./scenes/atrium/gen -o DIR    # DIR/atrium.glb and DIR/sky.hdr
//	farm render DIR/atrium.glb --environment DIR/sky.hdr -o out/
//
// Two floors of arcades around a courtyard open to the sky: 48 fluted marble columns
// (about 300,000 triangles), arches, brick walls with windows the sun shines through,
// tiled floors, red banners cut out by their texture's alpha, a bronze sphere on a marble
// pedestal, and one potted plant (leaves cut out by alpha) that 100 nodes place: a mesh
// stored once and instanced. Eleven textures, all drawn by this program; the sun is a
// KHR_lights_punctual directional light. Nothing is random but for fixed seeds, so the
// files are the same at every run.
package atrium

import (
	"bytes"
	"fmt"
	"math"
	"os"
	"path/filepath"

	"github.com/qmuntal/gltf"
	"github.com/qmuntal/gltf/ext/lightspunctual"
	"github.com/qmuntal/gltf/modeler"
)

// Stats says what Write made.
type Stats struct {
	Triangles, Textures, Nodes int
}

// Write writes dir/atrium.glb and dir/sky.hdr.
func Write(dir string) (Stats, error) {
	if err := os.MkdirAll(dir, 0o755); err != nil {
		return Stats{}, err
	}
	doc, triangles, err := atrium()
	if err != nil {
		return Stats{}, err
	}
	if err := gltf.SaveBinary(doc, filepath.Join(dir, "atrium.glb")); err != nil {
		return Stats{}, err
	}
	if err := os.WriteFile(filepath.Join(dir, "sky.hdr"), Sky(512, 256), 0o644); err != nil {
		return Stats{}, err
	}
	return Stats{Triangles: triangles, Textures: len(doc.Images), Nodes: len(doc.Nodes)}, nil
}

// builder adds meshes, materials and nodes to a glTF document.
type builder struct {
	doc       *gltf.Document
	textures  map[string]int
	triangles int
}

func (b *builder) texture(name string) *gltf.TextureInfo {
	return &gltf.TextureInfo{Index: b.textures[name]}
}

// material adds a metallic-roughness material and returns its index.
func (b *builder) material(m *gltf.Material) int {
	b.doc.Materials = append(b.doc.Materials, m)
	return len(b.doc.Materials) - 1
}

// mesh adds a mesh of one primitive per part (with its material) and returns its index.
func (b *builder) mesh(name string, parts []*part, materials []int) (int, error) {
	m := &gltf.Mesh{Name: name}
	for i, p := range parts {
		attrs, err := modeler.WritePrimitiveAttributes(b.doc,
			modeler.PrimitiveAttribute{Name: gltf.POSITION, Data: p.pos},
			modeler.PrimitiveAttribute{Name: gltf.NORMAL, Data: p.nrm},
			modeler.PrimitiveAttribute{Name: gltf.TEXCOORD_0, Data: p.uv})
		if err != nil {
			return 0, err
		}
		m.Primitives = append(m.Primitives, &gltf.Primitive{
			Attributes: attrs, Indices: gltf.Index(modeler.WriteIndices(b.doc, p.idx)), Material: gltf.Index(materials[i])})
		b.triangles += len(p.idx) / 3
	}
	b.doc.Meshes = append(b.doc.Meshes, m)
	return len(b.doc.Meshes) - 1, nil
}

// node adds a root node and returns its index.
func (b *builder) node(n *gltf.Node) int {
	if n.Rotation == [4]float64{} {
		n.Rotation = gltf.DefaultRotation
	}
	if n.Scale == [3]float64{} {
		n.Scale = gltf.DefaultScale
	}
	n.Matrix = gltf.DefaultMatrix
	b.doc.Nodes = append(b.doc.Nodes, n)
	i := len(b.doc.Nodes) - 1
	b.doc.Scenes[0].Nodes = append(b.doc.Scenes[0].Nodes, i)
	return i
}

// place adds a node that places mesh m.
func (b *builder) place(name string, m int, at [3]float64, turnY float64) {
	b.node(&gltf.Node{Name: name, Mesh: gltf.Index(m), Translation: at,
		Rotation: [4]float64{0, math.Sin(turnY / 2), 0, math.Cos(turnY / 2)}})
}

func atrium() (*gltf.Document, int, error) {
	doc := gltf.NewDocument()
	doc.Scenes = []*gltf.Scene{{Name: "atrium"}}
	doc.Scene = gltf.Index(0)
	b := &builder{doc: doc, textures: map[string]int{}}
	for _, t := range textures() {
		img, err := modeler.WriteImage(doc, t.name, "image/png", bytes.NewReader(pngBytes(t.img)))
		if err != nil {
			return nil, 0, err
		}
		doc.Textures = append(doc.Textures, &gltf.Texture{Name: t.name, Source: gltf.Index(img)})
		b.textures[t.name] = len(doc.Textures) - 1
	}
	pbr := func(base [4]float64, metal, rough float64, tex *gltf.TextureInfo, mr *gltf.TextureInfo) *gltf.PBRMetallicRoughness {
		return &gltf.PBRMetallicRoughness{BaseColorFactor: &base, MetallicFactor: gltf.Float(metal), RoughnessFactor: gltf.Float(rough),
			BaseColorTexture: tex, MetallicRoughnessTexture: mr}
	}
	white := [4]float64{1, 1, 1, 1}
	floor := b.material(&gltf.Material{Name: "floor tiles", PBRMetallicRoughness: pbr(white, 0, 0.7, b.texture("floor-albedo"), nil),
		NormalTexture: &gltf.NormalTexture{Index: gltf.Index(b.textures["floor-normal"])}})
	wall := b.material(&gltf.Material{Name: "brick", PBRMetallicRoughness: pbr(white, 0, 1, b.texture("wall-albedo"), b.texture("wall-roughness")),
		NormalTexture: &gltf.NormalTexture{Index: gltf.Index(b.textures["wall-normal"])}})
	marble := b.material(&gltf.Material{Name: "marble", PBRMetallicRoughness: pbr(white, 0, 0.3, b.texture("marble-albedo"), nil)})
	stone := b.material(&gltf.Material{Name: "arch stone", PBRMetallicRoughness: pbr(white, 0, 0.8, b.texture("arch-albedo"), nil)})
	banner := b.material(&gltf.Material{Name: "banner", PBRMetallicRoughness: pbr(white, 0, 0.9, b.texture("banner-albedo"), nil),
		AlphaMode: gltf.AlphaMask, AlphaCutoff: gltf.Float(0.5), DoubleSided: true})
	leaf := b.material(&gltf.Material{Name: "leaf", PBRMetallicRoughness: pbr(white, 0, 0.6, b.texture("leaf-albedo"), nil),
		AlphaMode: gltf.AlphaMask, AlphaCutoff: gltf.Float(0.5), DoubleSided: true})
	pot := b.material(&gltf.Material{Name: "terracotta", PBRMetallicRoughness: pbr(white, 0, 0.85, b.texture("pot-albedo"), nil)})
	bronze := b.material(&gltf.Material{Name: "bronze", PBRMetallicRoughness: pbr([4]float64{0.8, 0.5, 0.25, 1}, 1, 1, nil, b.texture("bronze-metallic-roughness"))})

	// The courtyard: x in [-12, 12], z in [-6, 6]; galleries of 2 m along the long sides;
	// two floors of 4 m (slab at 4 to 4.4), walls to 9 m.
	const halfX, halfZ, storey, slab, top = 12.0, 6.0, 4.0, 0.4, 9.0
	var ground part
	ground.quad([3]float64{-halfX, 0, halfZ}, [3]float64{2 * halfX, 0, 0}, [3]float64{0, 0, -2 * halfZ}, 2)
	var walls part
	// Long walls, with windows on the upper floor of the north wall (-z) the sun comes through.
	walls.box([3]float64{-halfX - 0.5, 0, halfZ}, [3]float64{halfX + 0.5, top, halfZ + 0.5}, 2)
	for x := -halfX; x < halfX; x += 3 {
		walls.box([3]float64{x, 0, -halfZ - 0.5}, [3]float64{x + 3, storey + slab + 1, -halfZ}, 2)
		walls.box([3]float64{x, top - 1.5, -halfZ - 0.5}, [3]float64{x + 3, top, -halfZ}, 2)
		walls.box([3]float64{x, storey + slab + 1, -halfZ - 0.5}, [3]float64{x + 1.2, top - 1.5, -halfZ}, 2)
	}
	walls.box([3]float64{-halfX - 0.5, 0, -halfZ - 0.5}, [3]float64{-halfX, top, halfZ + 0.5}, 2)
	walls.box([3]float64{halfX, 0, -halfZ - 0.5}, [3]float64{halfX + 0.5, top, halfZ + 0.5}, 2)
	// The galleries' floor slabs and roofs (the courtyard between them is open).
	var slabs part
	for _, z := range []float64{halfZ - 2, -halfZ} {
		slabs.box([3]float64{-halfX, storey, z}, [3]float64{halfX, storey + slab, z + 2}, 1)
		slabs.box([3]float64{-halfX, 2*storey + slab, z}, [3]float64{halfX, 2*storey + 2*slab, z + 2}, 1)
	}
	// Columns and arches on the courtyard side of each gallery, on both floors.
	var columns, arches part
	for _, z := range []float64{halfZ - 2, -halfZ + 2} {
		for _, y0 := range []float64{0, storey + slab} {
			for i := 0; i < 12; i++ {
				x := -11 + 2*float64(i)
				columns.column(x, z, y0, y0+storey-1, 0.22, 48, 64)
				if i < 11 {
					arches.arch(x, x+2, y0+storey-1, z-0.2, 0.4, 0.3, 24)
				}
			}
		}
	}
	// Banners hang from the upper arches on the south side, facing the courtyard.
	var banners part
	for i := 0; i < 6; i++ {
		x := -9 + 3.6*float64(i)
		banners.quadUV([3]float64{x - 0.5, storey + slab + 0.6, halfZ - 2.25}, [3]float64{1, 0, 0}, [3]float64{0, 2.2, 0}, 1, 1)
	}
	// The pedestal and the bronze sphere in the middle of the courtyard.
	var pedestal, ball part
	pedestal.box([3]float64{-0.6, 0, -0.6}, [3]float64{0.6, 1.1, 0.6}, 1)
	sphere(&ball, [3]float64{0, 1.9, 0}, 0.8, 48, 24)
	// One potted plant, placed 100 times along the galleries.
	var potPart, leaves part
	potPart.column(0, 0, 0, 0.45, 0.18, 24, 6)
	for k := 0; k < 24; k++ {
		a := 2 * math.Pi * float64(k) / 24
		tilt := 0.35 + 0.5*float64(k%3)/2
		base := [3]float64{0.05 * math.Cos(a), 0.4, 0.05 * math.Sin(a)}
		out := [3]float64{0.55 * math.Cos(a) * math.Cos(tilt), 0.55 * math.Sin(tilt), 0.55 * math.Sin(a) * math.Cos(tilt)}
		side := [3]float64{-0.12 * math.Sin(a), 0, 0.12 * math.Cos(a)}
		leaves.quadUV(sub(base, side), scale(side, 2), out, 1, 1)
	}

	add := func(name string, p *part, material int) error {
		m, err := b.mesh(name, []*part{p}, []int{material})
		if err != nil {
			return err
		}
		b.place(name, m, [3]float64{}, 0)
		return nil
	}
	for _, it := range []struct {
		name     string
		p        *part
		material int
	}{{"floor", &ground, floor}, {"walls", &walls, wall}, {"slabs", &slabs, stone}, {"columns", &columns, marble},
		{"arches", &arches, stone}, {"banners", &banners, banner}, {"pedestal", &pedestal, marble}, {"sphere", &ball, bronze}} {
		if err := add(it.name, it.p, it.material); err != nil {
			return nil, 0, err
		}
	}
	plant, err := b.mesh("potted plant", []*part{&potPart, &leaves}, []int{pot, leaf})
	if err != nil {
		return nil, 0, err
	}
	for i := 0; i < 100; i++ {
		side := halfZ - 1 - 0.5*float64(i%2)
		if i/50 == 1 {
			side = -side
		}
		x := -11.5 + 23*float64((i%50)/2)/24
		b.place(fmt.Sprintf("plant %d", i), plant, [3]float64{x, 0, side}, float64(i)*0.7)
	}

	// The sun: from high in the south-east, down through the courtyard and the north
	// wall's windows. A directional light shines along its node's -Z.
	sunDir := normalize3([3]float64{-0.35, -0.8, -0.5})
	doc.ExtensionsUsed = []string{lightspunctual.ExtensionName}
	doc.Extensions = gltf.Extensions{lightspunctual.ExtensionName: map[string]any{"lights": lightspunctual.Lights{
		{Type: lightspunctual.TypeDirectional, Name: "sun", Color: &[3]float64{1, 0.95, 0.85}, Intensity: gltf.Float(683 * 4)},
	}}}
	b.node(&gltf.Node{Name: "sun", Rotation: rotationFromMinusZ(sunDir),
		Extensions: gltf.Extensions{lightspunctual.ExtensionName: map[string]int{"light": 0}}})
	// The camera: in the west gallery's corner, looking along the courtyard.
	doc.Cameras = []*gltf.Camera{{Name: "view", Perspective: &gltf.Perspective{Yfov: 60 * math.Pi / 180, AspectRatio: gltf.Float(16.0 / 9), Znear: 0.1}}}
	eye, at := [3]float64{-11, 1.7, 4.5}, [3]float64{4, 3.2, -2.5}
	b.node(&gltf.Node{Name: "camera", Camera: gltf.Index(0), Translation: eye, Rotation: rotationFromMinusZ(normalize3(sub(at, eye)))})
	return doc, b.triangles, nil
}

// sphere adds a UV sphere.
func sphere(p *part, c [3]float64, r float64, segments, rings int) {
	base := uint32(len(p.pos))
	for j := 0; j <= rings; j++ {
		th := math.Pi * float64(j) / float64(rings)
		for i := 0; i <= segments; i++ {
			ph := 2 * math.Pi * float64(i) / float64(segments)
			n := [3]float64{math.Sin(th) * math.Cos(ph), math.Cos(th), math.Sin(th) * math.Sin(ph)}
			p.vertex(c[0]+r*n[0], c[1]+r*n[1], c[2]+r*n[2], n[0], n[1], n[2], float64(i)/float64(segments), float64(j)/float64(rings))
		}
	}
	row := uint32(segments + 1)
	for j := 0; j < rings; j++ {
		for i := 0; i < segments; i++ {
			a := base + uint32(j)*row + uint32(i)
			p.tri(a, a+1, a+row+1)
			p.tri(a, a+row+1, a+row)
		}
	}
}

func normalize3(v [3]float64) [3]float64 { return scale(v, 1/length(v)) }

// rotationFromMinusZ is the unit quaternion (x, y, z, w) that turns -Z to d (unit).
func rotationFromMinusZ(d [3]float64) [4]float64 {
	from := [3]float64{0, 0, -1}
	axis := cross(from, d)
	c := from[0]*d[0] + from[1]*d[1] + from[2]*d[2]
	if length(axis) < 1e-12 {
		if c > 0 {
			return [4]float64{0, 0, 0, 1}
		}
		return [4]float64{0, 1, 0, 0}
	}
	axis = normalize3(axis)
	a := math.Acos(math.Max(-1, math.Min(1, c)))
	s := math.Sin(a / 2)
	return [4]float64{axis[0] * s, axis[1] * s, axis[2] * s, math.Cos(a / 2)}
}
