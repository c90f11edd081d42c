package farmtest

import (
	"bytes"
	"encoding/binary"
)

// renderTimeAttribute is how the final EXR's renderTime attribute begins: its name, its
// type and the size of its value (a double).
var renderTimeAttribute = []byte("renderTime\x00double\x00\x08\x00\x00\x00")

// WithoutRenderTime returns a copy of a final EXR with the value of its renderTime
// attribute zeroed. That value, the seconds the job took until it was composited, is the
// one part of the file that differs between two renders of one scene, so renders compare
// byte for byte after it: the pixels and every other attribute. A file without the
// attribute comes back unchanged. OpenEXR writes the header first, so the first match is
// the attribute's.
func WithoutRenderTime(exr []byte) []byte {
	out := bytes.Clone(exr)
	i := bytes.Index(out, renderTimeAttribute)
	if i < 0 || len(out) < i+len(renderTimeAttribute)+8 {
		return out
	}
	binary.LittleEndian.PutUint64(out[i+len(renderTimeAttribute):], 0)
	return out
}
