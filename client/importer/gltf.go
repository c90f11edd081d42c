package importer

import (
	"context"
	"fmt"
	"path/filepath"

	"github.com/qmuntal/gltf"
	"github.com/qmuntal/gltf/ext/lightspunctual"

	"photonfarm/contract/assets"
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// The glTF extensions the importer reads. A file that requires any other is refused.
var knownExtensions = map[string]bool{
	lightspunctual.ExtensionName:      true,
	"KHR_materials_emissive_strength": true,
	"KHR_materials_transmission":      true,
	"KHR_materials_ior":               true,
}

// lumensPerWatt converts glTF's photometric light units (candela, lux) to the farm's
// radiometric ones: the luminous efficacy of 555 nm light (docs/import.md).
const lumensPerWatt = 683

func importGLTF(ctx context.Context, src string, w *writer, opt Options) (*Result, error) {
	lim := assets.SceneLimits()
	files := sourceFS{dir: filepath.Dir(src), limit: int64(lim.MaxBytes)}
	f, err := files.Open(filepath.Base(src))
	if err != nil {
		return nil, err
	}
	defer f.Close()
	doc := new(gltf.Document)
	if err := gltf.NewDecoderFS(f, files).Decode(doc); err != nil {
		return nil, fmt.Errorf("not a glTF file this farm can read: %v", err)
	}
	if err := ctx.Err(); err != nil {
		return nil, err
	}
	for _, e := range doc.ExtensionsRequired {
		if !knownExtensions[e] {
			return nil, fmt.Errorf("requires the extension %s, which this farm does not support", e)
		}
	}
	g := &gltfImport{build: newBuild(src), doc: doc, files: files, w: w,
		materials: map[int]string{}, textures: map[int]string{}, meshes: map[int]meshEntry{}}
	for _, e := range doc.ExtensionsUsed {
		if !knownExtensions[e] {
			g.skip("extension %s (optional)", e)
		}
	}
	if len(doc.Animations) > 0 {
		g.skip("%d animations (the farm renders one frame)", len(doc.Animations))
	}
	if len(doc.Skins) > 0 {
		g.skip("%d skins (meshes are rendered in their bind pose)", len(doc.Skins))
	}
	if err := g.walk(ctx); err != nil {
		return nil, err
	}
	return g.finish(g.w, opt)
}

type gltfImport struct {
	*build
	doc   *gltf.Document
	files sourceFS
	w     *writer
	// The farm's names of the glTF materials and images written so far, and the meshes.
	materials, textures map[int]string
	meshes              map[int]meshEntry
}

// walk visits the nodes of the default scene (every root node if none is named),
// parents before children, without recursion.
func (g *gltfImport) walk(ctx context.Context) error {
	roots, err := g.roots()
	if err != nil {
		return err
	}
	type visit struct {
		node  int
		world mat4
		depth int
	}
	seen := make([]bool, len(g.doc.Nodes))
	stack := make([]visit, 0, len(roots))
	for i := len(roots) - 1; i >= 0; i-- {
		stack = append(stack, visit{roots[i], identity(), 1})
	}
	for len(stack) > 0 {
		if err := ctx.Err(); err != nil {
			return err
		}
		v := stack[len(stack)-1]
		stack = stack[:len(stack)-1]
		if v.node < 0 || v.node >= len(g.doc.Nodes) {
			return fmt.Errorf("node %d does not exist (the file has %d)", v.node, len(g.doc.Nodes))
		}
		if seen[v.node] {
			return fmt.Errorf("node %d has two parents or is its own ancestor (glTF nodes form trees)", v.node)
		}
		seen[v.node] = true
		if v.depth > MaxNodeDepth {
			return fmt.Errorf("nodes nest more than %d deep (node %d)", MaxNodeDepth, v.node)
		}
		n := g.doc.Nodes[v.node]
		world := v.world.mul(localMatrix(n))
		if err := g.node(v.node, n, world); err != nil {
			return err
		}
		for i := len(n.Children) - 1; i >= 0; i-- {
			stack = append(stack, visit{n.Children[i], world, v.depth + 1})
		}
	}
	return nil
}

func (g *gltfImport) roots() ([]int, error) {
	if g.doc.Scene != nil {
		i := *g.doc.Scene
		if i < 0 || i >= len(g.doc.Scenes) {
			return nil, fmt.Errorf("the default scene %d does not exist", i)
		}
		return g.doc.Scenes[i].Nodes, nil
	}
	if len(g.doc.Scenes) > 0 {
		return g.doc.Scenes[0].Nodes, nil
	}
	// No scene: every node without a parent.
	child := make([]bool, len(g.doc.Nodes))
	for _, n := range g.doc.Nodes {
		for _, c := range n.Children {
			if c >= 0 && c < len(child) {
				child[c] = true
			}
		}
	}
	var roots []int
	for i := range g.doc.Nodes {
		if !child[i] {
			roots = append(roots, i)
		}
	}
	return roots, nil
}

// node places what node i holds: a mesh instance, a camera, a light.
func (g *gltfImport) node(i int, n *gltf.Node, world mat4) error {
	if world.det() == 0 || !world.finite() {
		return fmt.Errorf("node %d's transform is singular or not finite", i)
	}
	if n.Mesh != nil {
		name, b, err := g.mesh(*n.Mesh)
		if err != nil {
			return err
		}
		if name != "" {
			if limit := rules.MaxItems(&pb.Scene{}, "shapes"); uint64(len(g.scene.Shapes)) >= limit {
				return fmt.Errorf("more mesh instances than the %d shapes a scene may have", limit)
			}
			g.scene.Shapes = append(g.scene.Shapes, &pb.Shape{
				Name:     nodeName(i, n),
				Geometry: &pb.Shape_Instance{Instance: &pb.MeshInstance{Mesh: name, Transform: &pb.Transform{Matrix: world.rows()}}},
			})
			g.bounds = g.bounds.union(b.transformed(world))
		}
	}
	if n.Camera != nil && g.camera == nil {
		if err := g.cameraAt(*n.Camera, world); err != nil {
			return err
		}
	}
	if raw, ok := n.Extensions[lightspunctual.ExtensionName]; ok {
		if err := g.light(i, raw, world); err != nil {
			return err
		}
	}
	return nil
}

func nodeName(i int, n *gltf.Node) string {
	if n.Name != "" {
		return rules.Truncate(n.Name, 200)
	}
	return fmt.Sprintf("node %d", i)
}

// mesh writes glTF mesh i (once, however many nodes use it) and returns its farm name and
// its bounds; "" if none of its primitives are triangles.
func (g *gltfImport) mesh(i int) (string, box, error) {
	if i < 0 || i >= len(g.doc.Meshes) {
		return "", box{}, fmt.Errorf("mesh %d does not exist (the file has %d)", i, len(g.doc.Meshes))
	}
	if e, ok := g.meshes[i]; ok {
		return e.name, e.bounds, nil
	}
	m := g.doc.Meshes[i]
	mesh := &pb.Mesh{Name: fmt.Sprintf("mesh %d", i)}
	if m.Name != "" {
		mesh.Name = fmt.Sprintf("mesh %d (%s)", i, rules.Truncate(m.Name, 200))
	}
	var b box
	for j, p := range m.Primitives {
		part, pbox, err := g.primitive(i, j, p)
		if err != nil {
			return "", box{}, fmt.Errorf("mesh %d primitive %d: %w", i, j, err)
		}
		if part != nil {
			mesh.Parts = append(mesh.Parts, part)
			b = b.union(pbox)
		}
	}
	if len(mesh.Parts) == 0 {
		g.meshes[i] = meshEntry{}
		return "", box{}, nil
	}
	g.meshes[i] = meshEntry{mesh.Name, b}
	g.scene.Meshes = append(g.scene.Meshes, mesh)
	return mesh.Name, b, nil
}

// meshEntry is a glTF mesh as written: its farm name ("" if it had no triangles) and its
// bounds in its own space.
type meshEntry struct {
	name   string
	bounds box
}
