package photonmap

import (
	"cmp"
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

// buildTree reorders items into a left-balanced kd-tree and writes it into out
// (recordSize bytes per photon, node i at offset recordSize*i).
func buildTree(items []item, out []byte) {
	if len(items) == 0 {
		return
	}
	var wg sync.WaitGroup
	buildSubtree(items, 0, out, 0, &wg)
	wg.Wait()
}

func buildSubtree(s []item, node int, out []byte, depth int, wg *sync.WaitGroup) {
	for len(s) > 0 {
		if len(s) == 1 {
			writeNode(out, node, &s[0], axisLeaf)
			return
		}
		axis := widestAxis(s)
		left := leftSubtreeSize(len(s))
		selectRank(s, left, axis)
		writeNode(out, node, &s[left], axis)
		l, r := s[:left], s[left+1:]
		if depth < parallelDepth && len(s) >= parallelMinSize {
			wg.Add(1)
			go func(node, depth int) {
				defer wg.Done()
				buildSubtree(l, node, out, depth, wg)
			}(2*node+1, depth+1)
		} else {
			buildSubtree(l, 2*node+1, out, depth+1, wg)
		}
		// The right subtree continues in this loop rather than recursing.
		s, node, depth = r, 2*node+2, depth+1
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

func writeNode(out []byte, node int, it *item, axis int) {
	rec := out[recordSize*node : recordSize*node+recordSize]
	for c := 0; c < 3; c++ {
		le.PutUint32(rec[4*c:], math.Float32bits(it.pos[c]))
	}
	le.PutUint32(rec[12:], it.power)
	le.PutUint16(rec[16:], it.wi)
	le.PutUint16(rec[18:], it.normal|uint16(axis))
}
