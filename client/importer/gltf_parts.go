package importer

import (
	"encoding/base64"
	"encoding/json"
	"fmt"
	"math"
	"strings"

	"github.com/qmuntal/gltf"
	"github.com/qmuntal/gltf/ext/lightspunctual"
	"github.com/qmuntal/gltf/modeler"

	"photonfarm/contract/assets"
	pb "photonfarm/proto/renderfarm/v1"
)

// localMatrix is a node's transform: its matrix, or translation * rotation * scale.
func localMatrix(n *gltf.Node) mat4 {
	if n.Matrix != gltf.DefaultMatrix && n.Matrix != [16]float64{} {
		return fromColumnMajor(n.Matrix)
	}
	return trs(n.Translation, n.Rotation, n.Scale)
}

// primitive writes one primitive of mesh m as a farm mesh file and returns its part and
// bounds; nil for a primitive that is not made of triangles (skipped, and said so).
func (g *gltfImport) primitive(m, j int, p *gltf.Primitive) (*pb.MeshPart, box, error) {
	lim := assets.SceneLimits()
	switch p.Mode {
	case gltf.PrimitiveTriangles, gltf.PrimitiveTriangleStrip, gltf.PrimitiveTriangleFan:
	default:
		g.skip("mesh %d primitive %d: mode %s (only triangles are rendered)", m, j, p.Mode)
		return nil, box{}, nil
	}
	if len(p.Targets) > 0 {
		g.skip("mesh %d primitive %d: morph targets (rendered at rest)", m, j)
	}
	pos, ok := p.Attributes[gltf.POSITION]
	if !ok {
		return nil, box{}, fmt.Errorf("no POSITION attribute")
	}
	positions, err := vec3s(g.doc, pos, "POSITION", lim.MaxVertices)
	if err != nil {
		return nil, box{}, err
	}
	data := &assets.MeshData{}
	var b box
	for _, v := range positions {
		data.Positions = append(data.Positions, v[0], v[1], v[2])
		b = b.add([3]float64{float64(v[0]), float64(v[1]), float64(v[2])})
	}
	n := len(positions)
	if a, ok := p.Attributes[gltf.NORMAL]; ok {
		normals, err := vec3s(g.doc, a, "NORMAL", lim.MaxVertices)
		if err != nil {
			return nil, box{}, err
		}
		if len(normals) != n {
			return nil, box{}, fmt.Errorf("NORMAL has %d elements for %d positions", len(normals), n)
		}
		for _, v := range normals {
			data.Normals = append(data.Normals, v[0], v[1], v[2])
		}
	}
	if a, ok := p.Attributes[gltf.TEXCOORD_0]; ok {
		uv, err := texCoords(g.doc, a, lim.MaxVertices)
		if err != nil {
			return nil, box{}, err
		}
		if len(uv) != n {
			return nil, box{}, fmt.Errorf("TEXCOORD_0 has %d elements for %d positions", len(uv), n)
		}
		for _, v := range uv {
			data.TexCoords = append(data.TexCoords, v[0], v[1])
		}
	}
	if a, ok := p.Attributes[gltf.TANGENT]; ok && len(data.Normals) > 0 {
		t, err := tangents(g.doc, a, lim.MaxVertices)
		if err != nil {
			return nil, box{}, err
		}
		if len(t) != n {
			return nil, box{}, fmt.Errorf("TANGENT has %d elements for %d positions", len(t), n)
		}
		for _, v := range t {
			data.Tangents = append(data.Tangents, v[0], v[1], v[2], v[3])
		}
	}
	var idx []uint32
	if p.Indices != nil {
		if idx, err = indices(g.doc, *p.Indices, n, 3*lim.MaxTriangles); err != nil {
			return nil, box{}, err
		}
	} else {
		idx = make([]uint32, n)
		for i := range idx {
			idx[i] = uint32(i)
		}
	}
	if data.Indices = triangles(p.Mode, idx); len(data.Indices) == 0 {
		g.skip("mesh %d primitive %d: no triangles", m, j)
		return nil, box{}, nil
	}
	if uint64(len(data.Indices)/3) > lim.MaxTriangles {
		return nil, box{}, fmt.Errorf("%d triangles, more than the %d of one mesh", len(data.Indices)/3, lim.MaxTriangles)
	}
	material, err := g.material(p.Material)
	if err != nil {
		return nil, box{}, err
	}
	path, err := g.w.mesh(fmt.Sprintf("mesh%d-%d", m, j), data)
	if err != nil {
		return nil, box{}, err
	}
	return &pb.MeshPart{Path: path, Material: material}, b, nil
}

// triangles turns a primitive's indices into triangle lists (strips and fans unrolled,
// keeping each triangle's winding).
func triangles(mode gltf.PrimitiveMode, idx []uint32) []uint32 {
	switch mode {
	case gltf.PrimitiveTriangleStrip:
		var out []uint32
		for i := 0; i+2 < len(idx); i++ {
			if i%2 == 0 {
				out = append(out, idx[i], idx[i+1], idx[i+2])
			} else {
				out = append(out, idx[i+1], idx[i], idx[i+2])
			}
		}
		return out
	case gltf.PrimitiveTriangleFan:
		var out []uint32
		for i := 1; i+1 < len(idx); i++ {
			out = append(out, idx[0], idx[i], idx[i+1])
		}
		return out
	}
	return idx[:len(idx)/3*3]
}

// defaultMaterial is glTF's material for primitives that name none.
const defaultMaterial = "gltf default"

// material returns the farm name of glTF material i (nil: glTF's default material),
// writing it and its textures the first time.
func (g *gltfImport) material(i *int) (string, error) {
	key := -1
	if i != nil {
		key = *i
		if key < 0 || key >= len(g.doc.Materials) {
			return "", fmt.Errorf("material %d does not exist (the file has %d)", key, len(g.doc.Materials))
		}
	}
	if name, ok := g.materials[key]; ok {
		return name, nil
	}
	m := &gltf.Material{PBRMetallicRoughness: &gltf.PBRMetallicRoughness{}}
	name := defaultMaterial
	if key >= 0 {
		m = g.doc.Materials[key]
		name = fmt.Sprintf("material %d", key)
		if m.Name != "" {
			name = fmt.Sprintf("material %d (%s)", key, truncate(m.Name))
		}
	}
	out, err := g.convertMaterial(key, m)
	if err != nil {
		return "", fmt.Errorf("%s: %w", name, err)
	}
	out.Name = name
	g.scene.Materials = append(g.scene.Materials, out)
	g.materials[key] = name
	return name, nil
}

// convertMaterial maps a glTF material to the farm's: Principled, or Dielectric for a
// transmissive one (KHR_materials_transmission with KHR_materials_ior).
func (g *gltfImport) convertMaterial(key int, m *gltf.Material) (*pb.Material, error) {
	pbr := m.PBRMetallicRoughness
	if pbr == nil {
		pbr = &gltf.PBRMetallicRoughness{}
	}
	base := [4]float64{1, 1, 1, 1}
	if pbr.BaseColorFactor != nil {
		base = *pbr.BaseColorFactor
	}
	if t := extensionNumber(m.Extensions, "KHR_materials_transmission", "transmissionFactor", 0); t > 0 {
		ior := extensionNumber(m.Extensions, "KHR_materials_ior", "ior", 1.5)
		if ior < 1 {
			g.skip("material %d: an index of refraction of %v below 1 (1 used)", key, ior)
			ior = 1
		}
		if t < 1 {
			g.skip("material %d: transmission %v rendered as clear glass (transmission 1)", key, t)
		}
		return &pb.Material{Kind: &pb.Material_Dielectric{Dielectric: &pb.Dielectric{
			Ior: ior, Transmittance: color(base[0], base[1], base[2])}}}, nil
	}
	p := &pb.Principled{
		BaseColor:    color(base[0], base[1], base[2]),
		Metallic:     clamp01(pbr.MetallicFactorOrDefault()),
		Roughness:    clamp01(pbr.RoughnessFactorOrDefault()),
		Transparency: 1 - clamp01(base[3]),
	}
	var err error
	if p.BaseColorTexture, err = g.texture(pbr.BaseColorTexture); err != nil {
		return nil, err
	}
	if p.MetallicRoughnessTexture, err = g.texture(pbr.MetallicRoughnessTexture); err != nil {
		return nil, err
	}
	if nt := m.NormalTexture; nt != nil && nt.Index != nil {
		if p.NormalTexture, err = g.texture(&gltf.TextureInfo{Index: *nt.Index, TexCoord: nt.TexCoord}); err != nil {
			return nil, err
		}
		p.NormalScale = math.Min(math.Max(nt.ScaleOrDefault(), 0), 10)
	}
	if m.OcclusionTexture != nil {
		g.skip("material %d: its occlusion texture (light transport computes occlusion)", key)
	}
	strength := extensionNumber(m.Extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1)
	e := m.EmissiveFactor
	if e != [3]float64{} {
		p.Emission = color(e[0]*strength, e[1]*strength, e[2]*strength)
		g.emits = true
	}
	if p.EmissionTexture, err = g.texture(m.EmissiveTexture); err != nil {
		return nil, err
	}
	switch m.AlphaMode {
	case gltf.AlphaMask:
		p.AlphaMode = pb.AlphaMode_ALPHA_MODE_MASK
		p.AlphaCutoff = clamp01(m.AlphaCutoffOrDefault())
	case gltf.AlphaBlend:
		g.skip("material %d: alpha blending (rendered as a cut-out at opacity 0.5)", key)
		p.AlphaMode = pb.AlphaMode_ALPHA_MODE_MASK
		p.AlphaCutoff = 0.5
	}
	return &pb.Material{Kind: &pb.Material_Principled{Principled: p}}, nil
}

// texture returns a reference to the farm texture of a glTF texture info, writing its
// image the first time; nil for nil.
func (g *gltfImport) texture(info *gltf.TextureInfo) (*pb.TextureRef, error) {
	if info == nil {
		return nil, nil
	}
	if info.TexCoord != 0 {
		g.skip("texture %d read with TEXCOORD_%d (TEXCOORD_0 is used)", info.Index, info.TexCoord)
	}
	if info.Index < 0 || info.Index >= len(g.doc.Textures) {
		return nil, fmt.Errorf("texture %d does not exist (the file has %d)", info.Index, len(g.doc.Textures))
	}
	t := g.doc.Textures[info.Index]
	if t.Source == nil {
		return nil, fmt.Errorf("texture %d has no image", info.Index)
	}
	if name, ok := g.textures[info.Index]; ok {
		return &pb.TextureRef{Texture: name}, nil
	}
	path, err := g.image(*t.Source)
	if err != nil {
		return nil, err
	}
	name := fmt.Sprintf("texture %d", info.Index)
	tex := &pb.Texture{Name: name, Path: path}
	if t.Sampler != nil && *t.Sampler >= 0 && *t.Sampler < len(g.doc.Samplers) {
		switch g.doc.Samplers[*t.Sampler].WrapS {
		case gltf.WrapClampToEdge:
			tex.Wrap = pb.TextureWrap_TEXTURE_WRAP_CLAMP
		case gltf.WrapMirroredRepeat:
			tex.Wrap = pb.TextureWrap_TEXTURE_WRAP_MIRROR
		}
	}
	g.scene.Textures = append(g.scene.Textures, tex)
	g.textures[info.Index] = name
	return &pb.TextureRef{Texture: name}, nil
}

// image writes glTF image i (from a file beside the model, a data: URI or a buffer view)
// and returns its path, after checking it is an image the farm reads.
func (g *gltfImport) image(i int) (string, error) {
	if i < 0 || i >= len(g.doc.Images) {
		return "", fmt.Errorf("image %d does not exist (the file has %d)", i, len(g.doc.Images))
	}
	im := g.doc.Images[i]
	var data []byte
	var err error
	switch {
	case im.BufferView != nil:
		if *im.BufferView < 0 || *im.BufferView >= len(g.doc.BufferViews) {
			return "", fmt.Errorf("image %d names buffer view %d, which does not exist", i, *im.BufferView)
		}
		bv := g.doc.BufferViews[*im.BufferView]
		if bv.Buffer < 0 || bv.Buffer >= len(g.doc.Buffers) {
			return "", fmt.Errorf("image %d's buffer view names buffer %d, which does not exist", i, bv.Buffer)
		}
		data, err = modeler.ReadBufferView(g.doc, bv)
	case strings.HasPrefix(im.URI, "data:"):
		comma := strings.IndexByte(im.URI, ',')
		if comma < 0 || !strings.Contains(im.URI[:comma], ";base64") {
			return "", fmt.Errorf("image %d: a data: URI that is not base64", i)
		}
		data, err = base64.StdEncoding.DecodeString(im.URI[comma+1:])
	case im.URI != "":
		data, err = g.files.ReadFile(im.URI)
	default:
		return "", fmt.Errorf("image %d has neither a URI nor a buffer view", i)
	}
	if err != nil {
		return "", fmt.Errorf("image %d: %v", i, err)
	}
	t, err := checkImage(data)
	if err != nil {
		return "", fmt.Errorf("image %d (%s): %v", i, imageLabel(im), err)
	}
	stem := fmt.Sprintf("image%d", i)
	if im.Name != "" {
		stem += "-" + im.Name
	}
	return g.w.file("textures", stem, "."+extensionOf(t.Format), data)
}

func imageLabel(im *gltf.Image) string {
	if im.URI != "" && !strings.HasPrefix(im.URI, "data:") {
		return im.URI
	}
	if im.Name != "" {
		return im.Name
	}
	return "embedded"
}

func extensionOf(format string) string {
	switch format {
	case "jpeg":
		return "jpg"
	case "openexr":
		return "exr"
	}
	return format
}

// cameraAt makes the scene's camera of glTF camera i seen through a node's transform:
// glTF cameras look down their local -Z with +Y up.
func (g *gltfImport) cameraAt(i int, world mat4) error {
	if i < 0 || i >= len(g.doc.Cameras) {
		return fmt.Errorf("camera %d does not exist (the file has %d)", i, len(g.doc.Cameras))
	}
	c := g.doc.Cameras[i]
	if c.Perspective == nil {
		g.skip("camera %d: orthographic (a perspective camera framing the model is used)", i)
		return nil
	}
	pos := world.point([3]float64{})
	fwd := normalize(world.dir([3]float64{0, 0, -1}))
	up := normalize(world.dir([3]float64{0, 1, 0}))
	fov := c.Perspective.Yfov * 180 / math.Pi
	if !(fov > 0 && fov < 180) {
		return fmt.Errorf("camera %d: a vertical field of view of %v degrees", i, fov)
	}
	g.camera = &pb.Camera{
		Position:           vec(pos),
		LookAt:             vec([3]float64{pos[0] + fwd[0], pos[1] + fwd[1], pos[2] + fwd[2]}),
		Up:                 vec(up),
		VerticalFovDegrees: fov,
	}
	if a := c.Perspective.AspectRatio; a != nil && *a > 0 {
		g.aspect = *a
	}
	return nil
}

// light places the KHR_lights_punctual light a node names.
func (g *gltfImport) light(node int, raw any, world mat4) error {
	ref, err := lightIndex(raw)
	if err != nil {
		return fmt.Errorf("node %d: %v", node, err)
	}
	lights, _ := g.doc.Extensions[lightspunctual.ExtensionName].(lightspunctual.Lights)
	if ref < 0 || ref >= len(lights) {
		return fmt.Errorf("node %d names light %d, which does not exist (the file has %d)", node, ref, len(lights))
	}
	l := lights[ref]
	c, k := l.ColorOrDefault(), l.IntensityOrDefault()/lumensPerWatt
	power := color(c[0]*k, c[1]*k, c[2]*k)
	pos := vec(world.point([3]float64{}))
	dir := vec(normalize(world.dir([3]float64{0, 0, -1})))
	out := &pb.Light{Name: truncate(l.Name)}
	switch l.Type {
	case lightspunctual.TypePoint:
		out.Kind = &pb.Light_Point{Point: &pb.PointLight{Position: pos, Intensity: power}}
	case lightspunctual.TypeDirectional:
		out.Kind = &pb.Light_Sun{Sun: &pb.SunLight{Direction: dir, Irradiance: power}}
	case lightspunctual.TypeSpot:
		inner, outer := 0.0, math.Pi/4
		if l.Spot != nil {
			inner, outer = l.Spot.InnerConeAngle, l.Spot.OuterConeAngleOrDefault()
		}
		outer = math.Min(math.Max(outer*180/math.Pi, 1e-3), 90)
		inner = math.Min(math.Max(inner*180/math.Pi, 0), outer)
		out.Kind = &pb.Light_Spot{Spot: &pb.SpotLight{Position: pos, Direction: dir, Intensity: power,
			InnerConeDegrees: inner, OuterConeDegrees: outer}}
	default:
		return fmt.Errorf("light %d is of type %q, not point, spot or directional", ref, l.Type)
	}
	if l.Range != nil && !math.IsInf(*l.Range, 1) {
		g.skip("light %d: its range (lights fall off with the square of distance)", ref)
	}
	g.scene.Lights = append(g.scene.Lights, out)
	return nil
}

// lightIndex reads a node's KHR_lights_punctual extension: {"light": N}.
func lightIndex(raw any) (int, error) {
	switch v := raw.(type) {
	case lightspunctual.LightIndex:
		return int(v), nil
	case json.RawMessage:
		var ext struct {
			Light *int `json:"light"`
		}
		if err := json.Unmarshal(v, &ext); err != nil || ext.Light == nil {
			return 0, fmt.Errorf("a KHR_lights_punctual extension without a light index")
		}
		return *ext.Light, nil
	}
	return 0, fmt.Errorf("a KHR_lights_punctual extension of an unknown form %T", raw)
}

// extensionNumber reads a number from an extension the library leaves as raw JSON.
func extensionNumber(exts gltf.Extensions, name, field string, otherwise float64) float64 {
	raw, ok := exts[name].(json.RawMessage)
	if !ok {
		return otherwise
	}
	var m map[string]json.RawMessage
	if json.Unmarshal(raw, &m) != nil {
		return otherwise
	}
	var v float64
	if f, ok := m[field]; !ok || json.Unmarshal(f, &v) != nil || math.IsNaN(v) || math.IsInf(v, 0) {
		return otherwise
	}
	return v
}
