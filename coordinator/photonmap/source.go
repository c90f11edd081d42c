package photonmap

import (
	"bufio"
	"bytes"
	"errors"
	"io"
)

// Source opens one input of a build or a merge (an emission shard, a snapshot, an
// irradiance shard) for reading from its start. Build and MergeIrradiance read their
// inputs through sources, record by record, so that they hold no input whole: a shard is
// read twice (a pass to check it and find its map's power scale and bounds, a pass to
// gather its photons), a snapshot once. Errors of a source other than its end (a blob that
// is missing or damaged) are returned unchanged, so that the caller can tell them from a
// malformed input, which is an InvalidArgument error naming it.
type Source func() (io.ReadCloser, error)

// BytesSource is a Source of bytes in memory.
func BytesSource(data []byte) Source {
	return func() (io.ReadCloser, error) { return io.NopCloser(bytes.NewReader(data)), nil }
}

// scanner reads an input made of a fixed-size header and fixed-size records, one record
// at a time, and checks that the input ends exactly after the count of records its header
// announces.
type scanner struct {
	rc          io.ReadCloser
	r           *bufio.Reader
	count, read uint64 // records announced (set once the header is parsed) and read
	rec         []byte
	countField  string // the header field with the count: "record_count"
	wrong       func(format string, args ...any) error
}

// openScanner opens src and reads its header of headSize bytes; wrong makes the error of
// a malformed input (naming it).
func openScanner(src Source, headSize, recSize int, countField string, wrong func(string, ...any) error) (*scanner, []byte, error) {
	rc, err := src()
	if err != nil {
		return nil, nil, err
	}
	s := &scanner{rc: rc, r: bufio.NewReaderSize(rc, 1<<16), rec: make([]byte, recSize), countField: countField, wrong: wrong}
	head := make([]byte, headSize)
	if n, err := io.ReadFull(s.r, head); err != nil {
		rc.Close()
		if isShort(err) {
			return nil, nil, wrong("%d bytes is shorter than the %d-byte header", n, headSize)
		}
		return nil, nil, err
	}
	return s, head, nil
}

func (s *scanner) Close() error { return s.rc.Close() }

// next returns the next record, valid until the next call, or io.EOF once the input has
// ended right after the last record its header announces.
func (s *scanner) next() ([]byte, error) {
	if s.read == s.count {
		var b [1]byte
		n, err := s.r.Read(b[:])
		if n > 0 {
			return nil, s.wrong("%s %d does not match: more bytes follow the last record", s.countField, s.count)
		}
		return nil, err // io.EOF, or the source's verdict on its end
	}
	if _, err := io.ReadFull(s.r, s.rec); err != nil {
		if isShort(err) {
			return nil, s.wrong("%s %d does not match: the input ends after %d records", s.countField, s.count, s.read)
		}
		return nil, err
	}
	s.read++
	return s.rec, nil
}

func isShort(err error) bool { return errors.Is(err, io.ErrUnexpectedEOF) || errors.Is(err, io.EOF) }
