package photonmap

import (
	"bytes"
	"strings"
	"testing"
)

// TestDecodeRefusesADirectoryPastTheVolumeMap: a snapshot holds each of the three kinds at
// most once, in increasing order; Decode refuses any other directory.
func TestDecodeRefusesADirectoryPastTheVolumeMap(t *testing.T) {
	var three []Shard
	for _, tc := range testCases() {
		if tc.name == "three-maps" {
			three = tc.shards
		}
	}
	snap, err := Build(three)
	if err != nil {
		t.Fatal(err)
	}
	kindAt := func(entry int) int { return headerSize + entry*dirEntrySize }
	for _, tt := range []struct {
		name  string
		at    int
		value uint32
		want  string
	}{
		{"a fourth map", 16, maxMaps + 1, "map_count 4 > 3"},
		{"kind past volume", kindAt(2), uint32(Volume + 1), "map 2: unknown kind 4"},
		{"two caustic maps", kindAt(2), uint32(Caustic), "map 2: kinds not increasing"},
	} {
		t.Run(tt.name, func(t *testing.T) {
			forged := bytes.Clone(snap)
			le.PutUint32(forged[tt.at:], tt.value)
			if _, err := Decode(forged); err == nil || !strings.Contains(err.Error(), tt.want) {
				t.Errorf("Decode = %v, want an error with %q", err, tt.want)
			}
		})
	}
}
