package importer

import (
	"fmt"
	"math"

	"github.com/qmuntal/gltf"
	"github.com/qmuntal/gltf/modeler"

	"photonfarm/contract/rules"
)

// The glTF library reads accessors safely only once their ranges are known to lie inside
// their buffers: checkAccessor makes sure of that first (and of the element count, so
// that a hostile count cannot make it allocate gigabytes), then the library reads.

// checkAccessor refuses accessor i unless it is dense (not sparse), has a buffer view
// whose bytes lie inside its buffer, and its count elements (count at most maxCount) lie
// inside that view.
func checkAccessor(doc *gltf.Document, i int, maxCount uint64) (*gltf.Accessor, error) {
	if i < 0 || i >= len(doc.Accessors) {
		return nil, fmt.Errorf("accessor %d does not exist (the file has %d)", i, len(doc.Accessors))
	}
	a := doc.Accessors[i]
	switch {
	case a.Sparse != nil:
		return nil, fmt.Errorf("accessor %d is sparse, which this farm does not read", i)
	case a.BufferView == nil:
		return nil, fmt.Errorf("accessor %d has no buffer view", i)
	case a.Count <= 0:
		return nil, fmt.Errorf("accessor %d has %d elements", i, a.Count)
	case uint64(a.Count) > maxCount:
		return nil, fmt.Errorf("accessor %d has %d elements, more than the %d a mesh may have", i, a.Count, maxCount)
	case a.ByteOffset < 0:
		return nil, fmt.Errorf("accessor %d has a negative byte offset", i)
	}
	v := *a.BufferView
	if v < 0 || v >= len(doc.BufferViews) {
		return nil, fmt.Errorf("accessor %d names buffer view %d, which does not exist", i, v)
	}
	bv := doc.BufferViews[v]
	if bv.Buffer < 0 || bv.Buffer >= len(doc.Buffers) {
		return nil, fmt.Errorf("buffer view %d names buffer %d, which does not exist", v, bv.Buffer)
	}
	buf := doc.Buffers[bv.Buffer]
	if bv.ByteOffset < 0 || bv.ByteLength < 0 || int64(bv.ByteOffset)+int64(bv.ByteLength) > int64(len(buf.Data)) {
		return nil, fmt.Errorf("buffer view %d (bytes %d to %d) is longer than buffer %d's %d bytes",
			v, bv.ByteOffset, int64(bv.ByteOffset)+int64(bv.ByteLength), bv.Buffer, len(buf.Data))
	}
	elem := int64(a.ComponentType.ByteSize() * a.Type.Components())
	stride := int64(bv.ByteStride)
	if stride == 0 {
		stride = elem
	}
	if stride < elem {
		return nil, fmt.Errorf("buffer view %d has a stride of %d bytes, less than accessor %d's %d-byte elements", v, stride, i, elem)
	}
	if need := int64(a.ByteOffset) + stride*int64(a.Count-1) + elem; need > int64(bv.ByteLength) {
		return nil, fmt.Errorf("accessor %d needs %d bytes of buffer view %d, which has %d (a buffer shorter than its accessor)", i, need, v, bv.ByteLength)
	}
	return a, nil
}

// vec3s reads accessor i as float VEC3s (positions, normals), each finite.
func vec3s(doc *gltf.Document, i int, what string, maxCount uint64) ([][3]float32, error) {
	a, err := checkAccessor(doc, i, maxCount)
	if err != nil {
		return nil, err
	}
	var out [][3]float32
	if what == "POSITION" {
		out, err = modeler.ReadPosition(doc, a, nil)
	} else {
		out, err = modeler.ReadNormal(doc, a, nil)
	}
	if err != nil {
		return nil, fmt.Errorf("%s (accessor %d): %v", what, i, err)
	}
	for k, v := range out {
		for _, x := range v {
			if math.IsNaN(float64(x)) || math.IsInf(float64(x), 0) {
				return nil, fmt.Errorf("%s (accessor %d) element %d is not finite", what, i, k)
			}
			if m := rules.Scene.GetMaxMagnitude(); math.Abs(float64(x)) > m {
				return nil, fmt.Errorf("%s (accessor %d) element %d is past the largest magnitude %s", what, i, k, rules.Number(m))
			}
		}
	}
	return out, nil
}

// texCoords reads accessor i as TEXCOORD_0 (float, or normalised unsigned bytes or shorts).
func texCoords(doc *gltf.Document, i int, maxCount uint64) ([][2]float32, error) {
	a, err := checkAccessor(doc, i, maxCount)
	if err != nil {
		return nil, err
	}
	out, err := modeler.ReadTextureCoord(doc, a, nil)
	if err != nil {
		return nil, fmt.Errorf("TEXCOORD_0 (accessor %d): %v", i, err)
	}
	for k, v := range out {
		if math.IsNaN(float64(v[0]+v[1])) || math.IsInf(float64(v[0]+v[1]), 0) {
			return nil, fmt.Errorf("TEXCOORD_0 (accessor %d) element %d is not finite", i, k)
		}
	}
	return out, nil
}

// tangents reads accessor i as float VEC4 tangents, w = ±1.
func tangents(doc *gltf.Document, i int, maxCount uint64) ([][4]float32, error) {
	a, err := checkAccessor(doc, i, maxCount)
	if err != nil {
		return nil, err
	}
	out, err := modeler.ReadTangent(doc, a, nil)
	if err != nil {
		return nil, fmt.Errorf("TANGENT (accessor %d): %v", i, err)
	}
	for k, v := range out {
		for _, x := range v {
			if math.IsNaN(float64(x)) || math.IsInf(float64(x), 0) {
				return nil, fmt.Errorf("TANGENT (accessor %d) element %d is not finite", i, k)
			}
		}
		if v[3] != 1 && v[3] != -1 {
			v[3] = float32(math.Copysign(1, float64(v[3])))
			out[k] = v
		}
	}
	return out, nil
}

// indices reads accessor i as triangle indices, each less than vertices.
func indices(doc *gltf.Document, i int, vertices int, maxCount uint64) ([]uint32, error) {
	a, err := checkAccessor(doc, i, maxCount)
	if err != nil {
		return nil, err
	}
	if a.Type != gltf.AccessorScalar {
		return nil, fmt.Errorf("indices (accessor %d) are not scalars", i)
	}
	out, err := modeler.ReadIndices(doc, a, nil)
	if err != nil {
		return nil, fmt.Errorf("indices (accessor %d): %v", i, err)
	}
	for k, idx := range out {
		if int64(idx) >= int64(vertices) {
			return nil, fmt.Errorf("index %d (accessor %d, element %d) is out of range: the primitive has %d vertices", idx, i, k, vertices)
		}
	}
	return out, nil
}
