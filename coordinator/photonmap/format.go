// Package photonmap builds photon kd-tree snapshots from the emission shards that workers
// upload (both formats are specified in docs/photon-snapshot.md). Build is the product;
// Decode and EncodeShard exist for tests, test vectors and benchmarks.
package photonmap

import "fmt"

// Kind is a photon map's kind, as numbered in both formats.
type Kind uint32

const (
	Global  Kind = 1
	Caustic Kind = 2
	Volume  Kind = 3
	// maxMaps is how many maps a snapshot holds at most: one of each kind, as its
	// directory's kinds strictly increase.
	maxMaps = uint32(Volume)
)

func (k Kind) String() string {
	switch k {
	case Global:
		return "global"
	case Caustic:
		return "caustic"
	case Volume:
		return "volume"
	}
	return fmt.Sprintf("kind(%d)", uint32(k))
}

// known reports whether the formats define k.
func (k Kind) known() bool { return k >= Global && k <= Volume }

// Layout constants of the two formats.
const (
	shardMagic      = "PFSHARD1"
	shardVersion    = 1
	shardHeaderSize = 40
	shardRecordSize = 28

	snapshotMagic   = "PFPHOTON"
	snapshotVersion = 2
	headerSize      = 64
	dirEntrySize    = 64
	recordSize      = 20
	mapAlignment    = 64
	axisLeaf        = 3
	normalAxisMask  = 3
	maxMapPhotons   = 1<<31 - 1
	// The irradiance section (header bytes 32-47) and the IRRADIANCE SHARD format.
	irrOffsetAt        = 32
	irrCountAt         = 40
	irrScaleAt         = 44
	irrRecordSize      = 4
	irrShardMagic      = "PFIRRAD1"
	irrShardVersion    = 1
	irrShardHeaderSize = 40
	rgb9e5Bias         = 15
	rgb9e5MantBits     = 9
	rgb9e5MantLevels   = 1 << rgb9e5MantBits
)
