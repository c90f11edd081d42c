package photonmap

import (
	"encoding/binary"
	"fmt"
	"math"

	"photonfarm/coordinator/errs"
)

// Shard is one emission task's result in the SHARD format, as uploaded by a worker.
type Shard struct {
	Data []byte
}

// ShardPhoton is one record of a shard with its directions still oct-encoded.
type ShardPhoton struct {
	Position [3]float32
	Power    [3]float32
	Wi       uint16 // oct8
	Normal   uint16 // oct7 in bits 2-15, bits 0-1 zero
}

// shardHeader is a validated shard header; records start at shardHeaderSize.
type shardHeader struct {
	kind        Kind
	firstPhoton uint64
	photonCount uint64
	records     uint64 // as the header says; checked against the records read
}

var le = binary.LittleEndian

func shardErr(i int, format string, args ...any) error {
	return errs.Field(fmt.Sprintf("shards[%d]", i), format, args...)
}

// openShard opens shard i of a build and reads its header. Errors of the source (a blob
// that cannot be read) are returned unchanged; a malformed shard is an InvalidArgument
// error naming shards[i].
func openShard(i int, src Source) (*scanner, shardHeader, error) {
	wrong := func(format string, args ...any) error { return shardErr(i, format, args...) }
	s, head, err := openScanner(src, shardHeaderSize, shardRecordSize, "record_count", wrong)
	if err != nil {
		return nil, shardHeader{}, err
	}
	h, err := parseShardHeader(i, head)
	if err != nil {
		s.Close()
		return nil, shardHeader{}, err
	}
	s.count = h.records
	return s, h, nil
}

// nextShardRecord returns shard i's next record, checked (checkShardRecord), or io.EOF.
func nextShardRecord(i int, s *scanner) ([]byte, error) {
	rec, err := s.next()
	if err == nil {
		err = checkShardRecord(i, int(s.read-1), rec)
	}
	return rec, err
}

// parseShardHeader validates the header of shard i; its record count is checked against
// the records that follow as they are read.
func parseShardHeader(i int, head []byte) (shardHeader, error) {
	if string(head[:8]) != shardMagic {
		return shardHeader{}, shardErr(i, "bad magic %q, want %q", head[:8], shardMagic)
	}
	if v := le.Uint32(head[8:]); v != shardVersion {
		return shardHeader{}, shardErr(i, "unsupported version %d, want %d", v, shardVersion)
	}
	h := shardHeader{
		kind:        Kind(le.Uint32(head[12:])),
		firstPhoton: le.Uint64(head[16:]),
		photonCount: le.Uint64(head[24:]),
		records:     le.Uint64(head[32:]),
	}
	if !h.kind.known() {
		return shardHeader{}, shardErr(i, "unknown map kind %d", uint32(h.kind))
	}
	return h, nil
}

// checkShardRecord checks record r of shard i: a finite position, a finite power >= 0,
// the normal's reserved bits zero.
func checkShardRecord(i, r int, rec []byte) error {
	for c := 0; c < 3; c++ {
		p := math.Float32frombits(le.Uint32(rec[4*c:]))
		if math.IsNaN(float64(p)) || math.IsInf(float64(p), 0) {
			return shardErr(i, "record %d: position is not finite", r)
		}
		w := math.Float32frombits(le.Uint32(rec[12+4*c:]))
		if !(w >= 0) || math.IsInf(float64(w), 0) {
			return shardErr(i, "record %d: power must be finite and >= 0, got %g", r, w)
		}
	}
	if le.Uint16(rec[26:])&normalAxisMask != 0 {
		return shardErr(i, "record %d: normal bits 0-1 must be zero", r)
	}
	return nil
}

// shardPhoton reads a checked record.
func shardPhoton(rec []byte) ShardPhoton {
	var p ShardPhoton
	for c := 0; c < 3; c++ {
		p.Position[c] = math.Float32frombits(le.Uint32(rec[4*c:]))
		p.Power[c] = math.Float32frombits(le.Uint32(rec[12+4*c:]))
	}
	p.Wi = le.Uint16(rec[24:])
	p.Normal = le.Uint16(rec[26:])
	return p
}

// EncodeShard writes photons as a shard; the worker's C++ EncodeShard is the product's
// writer, this one serves tests, test vectors and benchmarks. It does not validate.
func EncodeShard(kind Kind, firstPhoton, photonCount uint64, photons []ShardPhoton) []byte {
	out := make([]byte, shardHeaderSize+shardRecordSize*len(photons))
	copy(out, shardMagic)
	le.PutUint32(out[8:], shardVersion)
	le.PutUint32(out[12:], uint32(kind))
	le.PutUint64(out[16:], firstPhoton)
	le.PutUint64(out[24:], photonCount)
	le.PutUint64(out[32:], uint64(len(photons)))
	for i, p := range photons {
		rec := out[shardHeaderSize+i*shardRecordSize:]
		for c := 0; c < 3; c++ {
			le.PutUint32(rec[4*c:], math.Float32bits(p.Position[c]))
			le.PutUint32(rec[12+4*c:], math.Float32bits(p.Power[c]))
		}
		le.PutUint16(rec[24:], p.Wi)
		le.PutUint16(rec[26:], p.Normal)
	}
	return out
}
