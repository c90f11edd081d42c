package vectorfiles

import (
	"fmt"
	"path"
	"testing"
)

// BinaryCase is one vector of a binary asset format (a farm mesh, a farm grid): a file and
// what every reader must make of it, Reason "" to accept it, else the byte offset and (part
// of) the reason of its refusal.
type BinaryCase struct {
	Name   string
	File   []byte
	Offset int64
	Reason string
}

// Cases are a generator's own case type, defined as BinaryCase (type gridCase
// vectorfiles.BinaryCase), so that its case tables may list fields by position.
type Cases interface {
	~struct {
		Name   string
		File   []byte
		Offset int64
		Reason string
	}
}

// BinaryVectors returns the files of cases, by path from the repository's root: each
// DIR/NAME.EXT beside NAME.EXT.vector, whose one line is "# vector: accept" or
// "# vector: refuse byte N: REASON".
func BinaryVectors[C Cases](dir, ext string, cases []C) map[string][]byte {
	files := map[string][]byte{}
	for _, each := range cases {
		c := BinaryCase(each)
		file := path.Join(dir, c.Name+ext)
		files[file] = c.File
		verdict := "# vector: accept"
		if c.Reason != "" {
			verdict = fmt.Sprintf("# vector: refuse byte %d: %s", c.Offset, c.Reason)
		}
		files[file+".vector"] = []byte(verdict + "\n")
	}
	return files
}

// CheckDistinctCases is CheckDistinct over binary cases.
func CheckDistinctCases[C Cases](t testing.TB, cases []C) {
	t.Helper()
	var names []string
	var files [][]byte
	for _, each := range cases {
		c := BinaryCase(each)
		names, files = append(names, c.Name), append(files, c.File)
	}
	CheckDistinct(t, names, files)
}
