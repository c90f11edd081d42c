// Package assetstest holds the asset files tests and the vector generators start from.
package assetstest

import (
	"bytes"
	"encoding/binary"
	"hash/crc32"

	"photonfarm/contract/assets"
)

// Quad is a unit square of two triangles with every optional section of a farm mesh file:
// normals, texture coordinates (v down: the top edge at v = 0) and tangents.
func Quad() *assets.MeshData {
	return &assets.MeshData{
		Positions: []float32{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0},
		Normals:   []float32{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1},
		TexCoords: []float32{0, 1, 1, 1, 1, 0, 0, 0},
		Tangents:  []float32{1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1},
		Indices:   []uint32{0, 1, 2, 0, 2, 3},
	}
}

// PNGHeader is a PNG signature and an IHDR chunk declaring w x h pixels (8-bit RGBA), with
// a valid CRC and nothing after it: what a huge image starts with.
func PNGHeader(w, h uint32) []byte {
	ihdr := make([]byte, 17)
	copy(ihdr, "IHDR")
	binary.BigEndian.PutUint32(ihdr[4:], w)
	binary.BigEndian.PutUint32(ihdr[8:], h)
	ihdr[12], ihdr[13] = 8, 6
	var b bytes.Buffer
	b.WriteString("\x89PNG\r\n\x1a\n")
	binary.Write(&b, binary.BigEndian, uint32(13))
	b.Write(ihdr)
	binary.Write(&b, binary.BigEndian, crc32.ChecksumIEEE(ihdr))
	return b.Bytes()
}

// RampGrid is a farm grid file of 3 x 2 x 2 cells over [-1, 2] x [0, 1] x [0, 0.5],
// densities 0, 0.25, ... 2.75 in file order (the first cell empty).
func RampGrid() *assets.GridData {
	g := &assets.GridData{Nx: 3, Ny: 2, Nz: 2, Min: [3]float32{-1, 0, 0}, Max: [3]float32{2, 1, 0.5}}
	for i := range 12 {
		g.Densities = append(g.Densities, 0.25*float32(i))
	}
	return g
}

// EncodedGrid is g as a farm grid file.
func EncodedGrid(g *assets.GridData) []byte {
	var b bytes.Buffer
	if err := assets.EncodeFarmGrid(&b, g); err != nil {
		panic(err) // the tests' grids are well formed
	}
	return b.Bytes()
}
