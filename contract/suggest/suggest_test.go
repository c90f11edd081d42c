package suggest

import "testing"

func TestDistance(t *testing.T) {
	for _, tc := range []struct {
		a, b string
		want int
	}{
		{"", "", 0},
		{"", "abc", 3},
		{"abc", "", 3},
		{"radius", "radius", 0},
		{"radus", "radius", 1},   // a deletion
		{"raddius", "radius", 1}, // an insertion
		{"radiux", "radius", 1},  // a substitution
		{"widht", "width", 1},    // a swap counts once
		{"kitten", "sitting", 3},
		{"ca", "abc", 3}, // the restricted distance: no edit of a swapped pair
		{"héllo", "hello", 1},
	} {
		if got := Distance(tc.a, tc.b); got != tc.want {
			t.Errorf("Distance(%q, %q) = %d, want %d", tc.a, tc.b, got, tc.want)
		}
		if got := Distance(tc.b, tc.a); got != tc.want {
			t.Errorf("Distance(%q, %q) = %d, want %d (symmetry)", tc.b, tc.a, got, tc.want)
		}
	}
}

func TestClosest(t *testing.T) {
	fields := []string{"width", "height", "tileSize", "tile_size"}
	for _, tc := range []struct {
		name       string
		candidates []string
		want       string
		ok         bool
	}{
		{"widht", fields, "width", true},
		{"hieght", fields, "height", true},
		{"TileSize", fields, "tileSize", true}, // case alone is no edit, still a hint
		{"tilesze", fields, "tileSize", true},  // the tie goes to the earlier name
		{"depth", fields, "", false},           // nothing near
		{"w", fields, "", false},               // one letter is too little to go on
		{"rendr", []string{"render", "report"}, "render", true},
		{"worker", []string{"workers", "worker-bin"}, "workers", true},
		{"anything", nil, "", false},
	} {
		got, ok := Closest(tc.name, tc.candidates)
		if got != tc.want && ok || ok != tc.ok {
			t.Errorf("Closest(%q) = %q, %v; want %q, %v", tc.name, got, ok, tc.want, tc.ok)
		}
		wantHint := ""
		if tc.ok {
			wantHint = ` (did you mean "` + tc.want + `"?)`
		}
		if h := Hint(tc.name, tc.candidates); h != wantHint {
			t.Errorf("Hint(%q) = %q, want %q", tc.name, h, wantHint)
		}
	}
}
