// Package suggest finds the known name closest to a misspelled one, for "did you mean"
// hints on scene fields, enum values, verbs and flags.
package suggest

import "strings"

// Distance is the optimal string alignment distance between a and b: the fewest
// insertions, deletions, substitutions and swaps of two adjacent letters that turn one
// into the other, counted in runes. A swap counts once because it is the commonest typo
// ("widht").
func Distance(a, b string) int {
	x, y := []rune(a), []rune(b)
	// Three rows of the table suffice: the swap looks two rows back.
	prev2 := make([]int, len(y)+1)
	prev := make([]int, len(y)+1)
	cur := make([]int, len(y)+1)
	for j := range prev {
		prev[j] = j
	}
	for i := 1; i <= len(x); i++ {
		cur[0] = i
		for j := 1; j <= len(y); j++ {
			cost := 1
			if x[i-1] == y[j-1] {
				cost = 0
			}
			cur[j] = min(prev[j]+1, cur[j-1]+1, prev[j-1]+cost)
			if i > 1 && j > 1 && x[i-1] == y[j-2] && x[i-2] == y[j-1] {
				cur[j] = min(cur[j], prev2[j-2]+1)
			}
		}
		prev2, prev, cur = prev, cur, prev2
	}
	return prev[len(y)]
}

// Closest returns the candidate nearest to name (ignoring case) if it is near enough to
// be the name meant: at most a third of name's length away (at least one edit). A tie
// goes to the earlier candidate, so callers list the likelier names first.
func Closest(name string, candidates []string) (string, bool) {
	lower := strings.ToLower(name)
	limit := max(1, len([]rune(name))/3)
	best, bestD := "", limit+1
	for _, c := range candidates {
		if d := Distance(lower, strings.ToLower(c)); d < bestD {
			best, bestD = c, d
		}
	}
	return best, bestD <= limit
}

// Hint is ` (did you mean "x"?)` for the candidate closest to name, or "" if none is
// near enough.
func Hint(name string, candidates []string) string {
	if c, ok := Closest(name, candidates); ok {
		return ` (did you mean "` + c + `"?)`
	}
	return ""
}
