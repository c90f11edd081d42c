package photonmap

import (
	"bytes"
	"strings"
	"testing"
)

func TestReadMapsAgreesWithDecodeReadingOnlyTheHead(t *testing.T) {
	for _, tc := range testCases() {
		snap, err := Build(tc.shards)
		if err != nil {
			t.Fatalf("%s: %v", tc.name, err)
		}
		full, err := Decode(snap)
		if err != nil {
			t.Fatalf("%s: %v", tc.name, err)
		}
		r := bytes.NewReader(snap)
		maps, err := ReadMaps(r, int64(len(snap)))
		if err != nil {
			t.Fatalf("%s: ReadMaps: %v", tc.name, err)
		}
		if len(maps) != len(full.Maps) {
			t.Fatalf("%s: %d maps, Decode has %d", tc.name, len(maps), len(full.Maps))
		}
		for i, m := range maps {
			if m.Kind != full.Maps[i].Kind || m.Photons != uint64(len(full.Maps[i].Photons)) {
				t.Errorf("%s: map %d = %+v, Decode has %s with %d photons", tc.name, i, m, full.Maps[i].Kind, len(full.Maps[i].Photons))
			}
		}
		if read, want := len(snap)-r.Len(), headerSize+dirEntrySize*len(maps); read != want {
			t.Errorf("%s: read %d bytes, want the header and directory's %d", tc.name, read, want)
		}
	}
}

func TestReadMapsRefusesWhatDecodeRefuses(t *testing.T) {
	snap, err := Build(testCases()[0].shards)
	if err != nil {
		t.Fatal(err)
	}
	for name, c := range map[string]struct {
		data []byte
		size int64
	}{
		"short of the header":       {snap[:headerSize-1], int64(len(snap))},
		"short of the directory":    {snap[:headerSize+dirEntrySize], int64(len(snap))},
		"size other than file_size": {snap, int64(len(snap)) - 1},
		"bad magic":                 {append([]byte("NOTPHOTN"), snap[8:]...), int64(len(snap))},
	} {
		if _, err := ReadMaps(bytes.NewReader(c.data), c.size); err == nil {
			t.Errorf("%s: ReadMaps accepted it", name)
		}
	}
}

// TestDecodeRefusesADirectoryPastTheVolumeMap: a snapshot holds each of the three kinds at
// most once, in increasing order; Decode and ReadMaps refuse any other directory.
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
			if _, err := ReadMaps(bytes.NewReader(forged), int64(len(forged))); err == nil || !strings.Contains(err.Error(), tt.want) {
				t.Errorf("ReadMaps = %v, want an error with %q", err, tt.want)
			}
		})
	}
}
