// Package assets checks the files a scene names before any work is queued: the client
// runs the checks before uploading, the coordinator again on submit (and plan), so that
// a broken file fails the submit with the file, the line and the reason instead of failing
// every worker. Meshes (Wavefront OBJ) are the one kind today.
//
// The OBJ checker is written by hand: OBJ is a small line-oriented text format, and no
// maintained Go OBJ library reports the line an error is on, which is the point here. It
// accepts what the worker's loader (tinyobjloader) reads and refuses, naming the line,
// what that loader would read wrongly or not at all. The shared vectors in
// tests/vectors/meshes run against this checker and the worker's loader alike.
//
// The rules, which the worker's side mirrors:
//
//   - Lines end in "\n"; a "\r" before it is dropped (CRLF). Lines are numbered from 1 and
//     at most max_mesh_line_bytes long, the line break included. The text is UTF-8 without NUL or other control
//     characters but tab: anything else is not a text file (binary garbage).
//   - Tokens are separated by spaces and tabs; a token starting with "#" starts a
//     comment to the end of the line. Blank lines and comments are ignored.
//   - "v x y z" declares a vertex, optionally followed by w or by a colour r g b (3, 4
//     or 6 numbers); "vt u [v [w]]" a texture coordinate (1 to 3); "vn x y z" a normal
//     (3). Numbers are decimal ("-1.5", "2e-3"), finite and at most
//     rules.Scene.max_magnitude in magnitude.
//   - "f" lists at least 3 vertex references, each v, v/vt, v//vn or v/vt/vn with
//     whole numbers: a positive index counts from 1 over the whole file (a face may name a
//     vertex declared after it, but not past the end of the file), a negative one back
//     from the latest declared before the face (-1 is the latest); 0 is no index. A face
//     of n vertices makes n - 2 triangles (a fan, as the worker triangulates it).
//   - Every other statement (o, g, s, usemtl, mtllib, l, p, and any this checker does
//     not know) is ignored, as tinyobjloader ignores them.
//   - The file has at most the limits' bytes, vertices and triangles, and at least one
//     triangle.
//
// Because positive indices may point forward, the checker reads the file twice: once to
// count its vertices, texture coordinates and normals, once to check every line against
// those counts. Memory stays constant whatever the file's size.
package assets

import (
	"bufio"
	"bytes"
	"context"
	"errors"
	"fmt"
	"io"
	"math"
	"strconv"
	"unicode/utf8"

	"photonfarm/contract/rules"
)

// Limits bound one mesh file: its size, vertices, triangles, and the length of a line
// with its line break (a face of some thousands of vertices fits in the contract's).
type Limits struct {
	MaxBytes, MaxVertices, MaxTriangles, MaxLineBytes uint64
}

// SceneLimits are the contract's limits of a mesh file (rules.Scene: max_asset_bytes,
// max_mesh_vertices, max_mesh_triangles).
func SceneLimits() Limits {
	return Limits{
		MaxBytes:     rules.Scene.GetMaxAssetBytes(),
		MaxVertices:  rules.Scene.GetMaxMeshVertices(),
		MaxTriangles: rules.Scene.GetMaxMeshTriangles(),
		MaxLineBytes: rules.Scene.GetMaxMeshLineBytes(),
	}
}

// Mesh is what checking an OBJ file learnt of it.
type Mesh struct {
	// Vertices counts the v statements, Triangles the triangles its faces make.
	Vertices, Triangles uint64
	// Min and Max bound the vertices.
	Min, Max [3]float64
}

// Error says which line of a file is wrong and why.
type Error struct {
	Line   int
	Reason string
}

func (e *Error) Error() string { return fmt.Sprintf("line %d: %s", e.Line, e.Reason) }

func (*Error) refused() {}

// Refusal is the error of a file that breaks the rules (an *Error of an OBJ file, a
// *FarmMeshError of a farm mesh file), as opposed to one that could not be read: callers
// tell the user what is wrong with the file.
type Refusal interface {
	error
	refused()
}

// Opener opens the file to check; CheckOBJ calls it twice and closes what it returns.
type Opener func() (io.ReadCloser, error)

// CheckOBJ reads the OBJ file open opens and checks it against the rules of the package
// comment and lim. It returns the mesh's counts and bounds, an *Error naming the first
// line that breaks a rule, the error of opening or reading the file, or ctx's error if ctx
// ends first.
func CheckOBJ(ctx context.Context, open Opener, lim Limits) (Mesh, error) {
	// The first pass only counts. It stops quietly at a line that is not text (or past a
	// limit): the second stops there too, unless a line before it is wrong first.
	var totals counts
	_, err := scan(ctx, open, lim, func(line []byte) error {
		switch string(firstToken(line)) {
		case "v":
			totals.v++
		case "vt":
			totals.vt++
		case "vn":
			totals.vn++
		}
		return nil
	})
	var e *Error
	if err != nil && !errors.As(err, &e) {
		return Mesh{}, err
	}
	c := checker{lim: lim, totals: totals}
	lines, err := scan(ctx, open, lim, func(line []byte) error {
		c.fields = tokens(c.fields[:0], line)
		if len(c.fields) == 0 {
			return nil
		}
		return c.statement(c.fields)
	})
	if err != nil {
		return Mesh{}, err
	}
	if c.mesh.Triangles == 0 {
		return Mesh{}, &Error{Line: max(lines, 1), Reason: "the mesh has no triangles (the file has no face)"}
	}
	return c.mesh, nil
}

type counts struct{ v, vt, vn uint64 }

// scan calls fn with every line of the file (without its line break) and returns the
// number of lines; an error of fn is an *Error naming the line.
func scan(ctx context.Context, open Opener, lim Limits, fn func(line []byte) error) (int, error) {
	f, err := open()
	if err != nil {
		return 0, err
	}
	defer f.Close()
	r := bufio.NewReaderSize(&limitedReader{ctx: ctx, r: f, left: lim.MaxBytes}, int(lim.MaxLineBytes))
	for line := 1; ; line++ {
		text, err := r.ReadSlice('\n')
		if len(text) == 0 && err == io.EOF {
			return line - 1, nil
		}
		text = bytes.TrimSuffix(bytes.TrimSuffix(text, []byte("\n")), []byte("\r"))
		// Binary garbage is named as such even in a line too long or past the limit.
		if reason := notText(text, err != nil && err != io.EOF); reason != "" {
			return line, &Error{Line: line, Reason: reason}
		}
		switch {
		case errors.Is(err, bufio.ErrBufferFull):
			return line, &Error{Line: line, Reason: fmt.Sprintf("is longer than %d bytes", lim.MaxLineBytes)}
		case errors.Is(err, errTooLarge):
			return line, &Error{Line: line, Reason: fmt.Sprintf("the file is larger than the limit of %d bytes", lim.MaxBytes)}
		case err != nil && err != io.EOF:
			return line, err
		}
		if ferr := fn(text); ferr != nil {
			return line, &Error{Line: line, Reason: ferr.Error()}
		}
		if err == io.EOF {
			return line, nil
		}
	}
}

// notText says why a line is not text, or "" if it is; a partial line (cut at the buffer
// or the size limit) may end inside a character.
func notText(line []byte, partial bool) string {
	for _, b := range line {
		switch {
		case b == 0:
			return "contains a NUL byte: not a text file"
		case (b < ' ' && b != '\t') || b == 0x7f:
			return fmt.Sprintf("contains the control character 0x%02x: not a text file", b)
		}
	}
	if partial {
		for i := len(line) - 1; i >= 0 && i >= len(line)-utf8.UTFMax; i-- {
			if utf8.RuneStart(line[i]) {
				if !utf8.FullRune(line[i:]) {
					line = line[:i]
				}
				break
			}
		}
	}
	if !utf8.Valid(line) {
		return "is not UTF-8 text: not a text file"
	}
	return ""
}

// tokens appends to fields the tokens of line (split at spaces and tabs) up to one that
// starts a comment.
func tokens(fields [][]byte, line []byte) [][]byte {
	for len(line) > 0 {
		tok, rest := nextToken(line)
		if len(tok) == 0 || tok[0] == '#' {
			break
		}
		fields, line = append(fields, tok), rest
	}
	return fields
}

// firstToken is tokens(line)[0], or nil.
func firstToken(line []byte) []byte {
	tok, _ := nextToken(line)
	if len(tok) > 0 && tok[0] == '#' {
		return nil
	}
	return tok
}

// nextToken returns the first token of line and what follows it.
func nextToken(line []byte) (tok, rest []byte) {
	i := 0
	for i < len(line) && (line[i] == ' ' || line[i] == '\t') {
		i++
	}
	j := i
	for j < len(line) && line[j] != ' ' && line[j] != '\t' {
		j++
	}
	return line[i:j], line[j:]
}

var errTooLarge = errors.New("too large")

// limitedReader reads at most left bytes (then fails with errTooLarge) and stops when
// ctx ends.
type limitedReader struct {
	ctx  context.Context
	r    io.Reader
	left uint64
}

func (l *limitedReader) Read(p []byte) (int, error) {
	if err := l.ctx.Err(); err != nil {
		return 0, err
	}
	if l.left == 0 {
		// One byte more says whether the file goes on past the limit.
		var one [1]byte
		if n, _ := l.r.Read(one[:]); n > 0 {
			return 0, errTooLarge
		}
		return l.r.Read(p)
	}
	if uint64(len(p)) > l.left {
		p = p[:l.left]
	}
	n, err := l.r.Read(p)
	l.left -= uint64(n)
	return n, err
}

// checker checks the statements of a file whose totals are known.
type checker struct {
	lim    Limits
	totals counts
	// seen counts the statements so far (negative indices count back from them).
	seen counts
	mesh Mesh
	// fields is the current line's tokens (reused from line to line).
	fields [][]byte
}

func (c *checker) statement(fields [][]byte) error {
	args := fields[1:]
	switch string(fields[0]) {
	case "v":
		if n := len(args); n != 3 && n != 4 && n != 6 {
			return fmt.Errorf("a vertex has 3 coordinates (then optionally w, or a colour r g b), got %d numbers", n)
		}
		var p [3]float64
		for i, a := range args {
			x, err := number(a)
			if err != nil {
				return err
			}
			if i < 3 {
				p[i] = x
			}
		}
		c.seen.v++
		if c.seen.v > c.lim.MaxVertices {
			return fmt.Errorf("the mesh has more than %d %s (the limit of one mesh)", c.lim.MaxVertices, plural(c.lim.MaxVertices, "vertex"))
		}
		c.extend(p)
	case "vt":
		if n := len(args); n < 1 || n > 3 {
			return fmt.Errorf("a texture coordinate has 1 to 3 numbers, got %d", n)
		}
		if err := numbers(args); err != nil {
			return err
		}
		c.seen.vt++
	case "vn":
		if n := len(args); n != 3 {
			return fmt.Errorf("a normal has 3 numbers, got %d", n)
		}
		if err := numbers(args); err != nil {
			return err
		}
		c.seen.vn++
	case "f":
		return c.face(args)
	}
	return nil
}

func (c *checker) extend(p [3]float64) {
	if c.mesh.Vertices == 0 {
		c.mesh.Min, c.mesh.Max = p, p
	}
	for i := range p {
		c.mesh.Min[i] = math.Min(c.mesh.Min[i], p[i])
		c.mesh.Max[i] = math.Max(c.mesh.Max[i], p[i])
	}
	c.mesh.Vertices++
}

func (c *checker) face(refs [][]byte) error {
	if len(refs) < 3 {
		return fmt.Errorf("a face needs at least 3 vertices, got %d", len(refs))
	}
	kinds := [3]struct {
		name        string
		total, seen uint64
	}{{"vertex", c.totals.v, c.seen.v}, {"texture coordinate", c.totals.vt, c.seen.vt}, {"normal", c.totals.vn, c.seen.vn}}
	for _, ref := range refs {
		var parts [3][]byte
		n := 0
		for rest := ref; ; n++ {
			if n == len(parts) {
				return badRef(ref)
			}
			i := bytes.IndexByte(rest, '/')
			if i < 0 {
				parts[n] = rest
				n++
				break
			}
			parts[n], rest = rest[:i], rest[i+1:]
		}
		if (n == 3 && len(parts[2]) == 0) || (n == 2 && len(parts[1]) == 0) {
			return badRef(ref)
		}
		for i, part := range parts[:n] {
			if i > 0 && len(part) == 0 {
				continue // v//vn: no texture coordinate
			}
			idx, ok := integer(part)
			if !ok {
				return badRef(ref)
			}
			k := kinds[i]
			switch {
			case idx == 0:
				return fmt.Errorf("face refers to %s 0, but OBJ counts from 1", k.name)
			case idx > 0 && uint64(idx) > k.total:
				return fmt.Errorf("face refers to %s %d but the file has %d %s", k.name, idx, k.total, plural(k.total, k.name))
			case idx < 0 && uint64(-idx) > k.seen:
				return fmt.Errorf("face refers to %s %d but only %d %s come before it", k.name, idx, k.seen, plural(k.seen, k.name))
			}
		}
	}
	c.mesh.Triangles += uint64(len(refs) - 2)
	if c.mesh.Triangles > c.lim.MaxTriangles {
		return fmt.Errorf("the mesh has more than %d %s (the limit of one mesh)", c.lim.MaxTriangles, plural(c.lim.MaxTriangles, "triangle"))
	}
	return nil
}

// integer parses [+-] digits into an int64; ok is false for anything else or an overflow.
func integer(b []byte) (v int64, ok bool) {
	neg := false
	if len(b) > 0 && (b[0] == '+' || b[0] == '-') {
		neg, b = b[0] == '-', b[1:]
	}
	if len(b) == 0 {
		return 0, false
	}
	for _, c := range b {
		if c < '0' || c > '9' || v > (math.MaxInt64-int64(c-'0'))/10 {
			return 0, false
		}
		v = 10*v + int64(c-'0')
	}
	if neg {
		v = -v
	}
	return v, true
}

// word is a word of the file as a message shows it: cut short, since it may be anything.
func word(b []byte) string { return rules.Truncate(string(b), 40) }

func badRef(ref []byte) error {
	return fmt.Errorf("%q is not a vertex reference (v, v/vt, v//vn or v/vt/vn, whole numbers)", word(ref))
}

func plural(n uint64, name string) string {
	switch {
	case n == 1:
		return name
	case name == "vertex":
		return "vertices"
	}
	return name + "s"
}

func numbers(args [][]byte) error {
	for _, a := range args {
		if _, err := number(a); err != nil {
			return err
		}
	}
	return nil
}

// number parses a decimal number ("-1.5", "2e-3"; not "inf", "nan" or hexadecimal),
// finite and within the scene's largest magnitude.
func number(tok []byte) (float64, error) {
	if !decimal(tok) {
		return 0, fmt.Errorf("%q is not a number", word(tok))
	}
	x, err := strconv.ParseFloat(string(tok), 64)
	if err != nil || math.IsInf(x, 0) {
		return 0, fmt.Errorf("%q is not a finite number", word(tok))
	}
	if m := rules.Scene.GetMaxMagnitude(); math.Abs(x) > m {
		return 0, fmt.Errorf("%s is out of range: numbers are at most ±%s", word(tok), rules.Number(m))
	}
	return x, nil
}

// decimal reports whether tok is [+-] digits [. digits] [e [+-] digits], with digits on
// at least one side of the point.
func decimal(tok []byte) bool {
	i := 0
	if i < len(tok) && (tok[i] == '+' || tok[i] == '-') {
		i++
	}
	digits := func() int {
		start := i
		for i < len(tok) && tok[i] >= '0' && tok[i] <= '9' {
			i++
		}
		return i - start
	}
	n := digits()
	if i < len(tok) && tok[i] == '.' {
		i++
		n += digits()
	}
	if n == 0 {
		return false
	}
	if i < len(tok) && (tok[i] == 'e' || tok[i] == 'E') {
		i++
		if i < len(tok) && (tok[i] == '+' || tok[i] == '-') {
			i++
		}
		if digits() == 0 {
			return false
		}
	}
	return i == len(tok)
}
