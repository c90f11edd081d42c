package photonmap

import (
	"cmp"
	"io"
	"math"
	"math/bits"
	"slices"
	"sync"
)

// item is a photon while the tree is built: its encoded payload and its index in the map's
// input order, which breaks ties so the tree is a function of the input alone. 24 bytes,
// moved by value: partitioning a flat slice is far faster than chasing indices.
type item struct {
	pos    [3]float32
	power  uint32
	wi     uint16
	normal uint16
	src    uint32
}

func less(a, b *item, axis int) bool {
	if a.pos[axis] != b.pos[axis] {
		return a.pos[axis] < b.pos[axis]
	}
	return a.src < b.src
}

// Subtrees larger than this are built on their own goroutine, down to parallelDepth levels:
// the output is the same whatever runs where, since subtrees write disjoint nodes.
const (
	parallelMinSize = 1 << 16
	parallelDepth   = 3
)

// treeWriter writes one map's nodes into out, node i at base + recordSize*i. A subtree of
// at most block photons is built in a buffer of its own and written a level at a time:
// each level of a subtree of the implicit tree is one contiguous run of the array, so a
// block of b photons costs about log2(b) positioned writes, and the output can be a file
// (the build never holds it) without a system call per node. Nodes above the blocks are
// written one by one: about 2N/block of them.
type treeWriter struct {
	out   io.WriterAt
	base  int64
	block int
	bufs  sync.Pool // *[]byte of recordSize*block
	mu    sync.Mutex
	err   error // the first write's error; the build stops writing after it
}

func (w *treeWriter) failed() bool {
	w.mu.Lock()
	defer w.mu.Unlock()
	return w.err != nil
}

func (w *treeWriter) write(p []byte, node int) {
	if _, err := w.out.WriteAt(p, w.base+int64(recordSize)*int64(node)); err != nil {
		w.mu.Lock()
		if w.err == nil {
			w.err = err
		}
		w.mu.Unlock()
	}
}

// buildTree reorders items into a left-balanced kd-tree and writes it through w.
func buildTree(items []item, w *treeWriter) error {
	if len(items) == 0 {
		return nil
	}
	var wg sync.WaitGroup
	buildSubtree(items, 0, w, 0, &wg)
	wg.Wait()
	return w.err
}

func buildSubtree(s []item, node int, w *treeWriter, depth int, wg *sync.WaitGroup) {
	for len(s) > 0 && !w.failed() {
		if len(s) <= w.block {
			w.writeBlock(s, node)
			return
		}
		axis, left := splitNode(s)
		var rec [recordSize]byte
		encodeNode(rec[:], &s[left], axis)
		w.write(rec[:], node)
		l, r := s[:left], s[left+1:]
		if depth < parallelDepth && len(s) >= parallelMinSize {
			wg.Add(1)
			go func(node, depth int) {
				defer wg.Done()
				buildSubtree(l, node, w, depth, wg)
			}(2*node+1, depth+1)
		} else {
			buildSubtree(l, 2*node+1, w, depth+1, wg)
		}
		// The right subtree continues in this loop rather than recursing.
		s, node, depth = r, 2*node+2, depth+1
	}
}

// splitNode chooses the axis of a subtree of at least 2 photons and moves its node, the
// photon of rank L on that axis, to s[L]: smaller ones before it, larger after.
func splitNode(s []item) (axis, left int) {
	axis = widestAxis(s)
	left = leftSubtreeSize(len(s))
	selectRank(s, left, axis)
	return axis, left
}

// writeBlock builds the subtree of s rooted at node in a buffer, numbered as a tree of its
// own (local node j has children 2j+1 and 2j+2, as in the whole), and writes it a level at a
// time: local level l, nodes [2^l - 1, 2^(l+1) - 1), is the run of global nodes starting at
// (node+1)*2^l - 1.
func (w *treeWriter) writeBlock(s []item, node int) {
	p, _ := w.bufs.Get().(*[]byte)
	if p == nil {
		b := make([]byte, recordSize*w.block)
		p = &b
	}
	defer w.bufs.Put(p)
	buf := *p
	buildLocal(s, 0, buf)
	for level := 0; ; level++ {
		first := 1<<level - 1
		if first >= len(s) {
			return
		}
		count := min(1<<level, len(s)-first)
		w.write(buf[recordSize*first:recordSize*(first+count)], (node+1)<<level-1)
	}
}

// buildLocal builds the subtree of s rooted at local node `node` into buf.
func buildLocal(s []item, node int, buf []byte) {
	for len(s) > 0 {
		if len(s) == 1 {
			encodeNode(buf[recordSize*node:], &s[0], axisLeaf)
			return
		}
		axis, left := splitNode(s)
		encodeNode(buf[recordSize*node:], &s[left], axis)
		buildLocal(s[:left], 2*node+1, buf)
		s, node = s[left+1:], 2*node+2
	}
}

// leftSubtreeSize is the size of the left subtree of a left-balanced tree of m >= 2 nodes:
// the full levels above the last one split evenly, and the left takes the last level's
// nodes first, up to half of that level's capacity.
func leftSubtreeSize(m int) int {
	h := bits.Len(uint(m)) - 1 // floor(log2 m): the depth of the last level
	half := 1 << (h - 1)       // capacity of the left subtree's part of the last level
	return half - 1 + min(m-(1<<h-1), half)
}

// widestAxis is the axis of the largest extent of s's bounding box, x before y before z.
func widestAxis(s []item) int {
	lo, hi := s[0].pos, s[0].pos
	for i := range s {
		for c := 0; c < 3; c++ {
			lo[c] = min(lo[c], s[i].pos[c])
			hi[c] = max(hi[c], s[i].pos[c])
		}
	}
	axis := 0
	for c := 1; c < 3; c++ {
		// Extents in float64: hi - lo of two finite float32s cannot overflow there.
		if float64(hi[c])-float64(lo[c]) > float64(hi[axis])-float64(lo[axis]) {
			axis = c
		}
	}
	return axis
}

// selectRank reorders s so that s[k] is the element of rank k by (pos[axis], src), with
// smaller ones before it and larger ones after: a quickselect with median-of-three pivots
// that falls back to a sort (O(n log n) worst case) if a hostile input defeats the pivots.
func selectRank(s []item, k, axis int) {
	lo, hi := 0, len(s)
	budget := 2 * bits.Len(uint(len(s)))
	for hi-lo > 16 {
		if budget == 0 {
			slices.SortFunc(s[lo:hi], func(a, b item) int {
				if c := cmp.Compare(a.pos[axis], b.pos[axis]); c != 0 {
					return c
				}
				return cmp.Compare(a.src, b.src)
			})
			return
		}
		budget--
		p := lo + partition(s[lo:hi], axis)
		switch {
		case k == p:
			return
		case k < p:
			hi = p
		default:
			lo = p + 1
		}
	}
	insertionSort(s[lo:hi], axis)
}

// partition puts a median-of-three pivot at its final place and returns it. Keys are
// distinct (src is unique), so nothing compares equal to the pivot but itself.
func partition(s []item, axis int) int {
	n := len(s)
	m := n / 2
	if less(&s[m], &s[0], axis) {
		s[m], s[0] = s[0], s[m]
	}
	if less(&s[n-1], &s[m], axis) {
		s[n-1], s[m] = s[m], s[n-1]
		if less(&s[m], &s[0], axis) {
			s[m], s[0] = s[0], s[m]
		}
	}
	s[0], s[m] = s[m], s[0]
	p := s[0]
	i, j := 1, n-1
	for {
		for i <= j && less(&s[i], &p, axis) {
			i++
		}
		for i <= j && less(&p, &s[j], axis) {
			j--
		}
		if i >= j {
			break
		}
		s[i], s[j] = s[j], s[i]
		i++
		j--
	}
	s[0], s[j] = s[j], s[0]
	return j
}

func insertionSort(s []item, axis int) {
	for i := 1; i < len(s); i++ {
		for j := i; j > 0 && less(&s[j], &s[j-1], axis); j-- {
			s[j], s[j-1] = s[j-1], s[j]
		}
	}
}

// encodeNode writes it as a snapshot record with the given split axis into rec.
func encodeNode(rec []byte, it *item, axis int) {
	for c := 0; c < 3; c++ {
		le.PutUint32(rec[4*c:], math.Float32bits(it.pos[c]))
	}
	le.PutUint32(rec[12:], it.power)
	le.PutUint16(rec[16:], it.wi)
	le.PutUint16(rec[18:], it.normal|uint16(axis))
}
