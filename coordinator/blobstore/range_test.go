package blobstore_test

import (
	"bytes"
	"context"
	"io"
	"testing"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/errs"
)

// OpenRange reads exactly the bytes of a range on every backend: from the start, in the
// middle, to the end, with a length of 0 (the rest) or past the end (cut at it), and an
// empty range at the end; an offset past the end is OutOfRange, an absent blob NotFound.
func TestOpenRangeReadsTheRangesBytes(t *testing.T) {
	forEachBackend(t, func(t *testing.T, open func(int64) (*blobstore.Store, raw)) {
		ctx := context.Background()
		s, _ := open(0)
		data := make([]byte, 3<<20+17)
		for i := range data {
			data[i] = byte(i * 7 / 5)
		}
		digest := rules.DigestOf(data)
		if _, err := s.Put(ctx, bytes.NewReader(data), int64(len(data)), digest); err != nil {
			t.Fatal(err)
		}
		n := int64(len(data))
		for _, tc := range []struct {
			offset, length int64
			want           []byte
		}{
			{0, 0, data},
			{0, 1 << 20, data[:1<<20]},
			{1<<20 + 3, 1 << 20, data[1<<20+3 : 2<<20+3]},
			{n - 5, 0, data[n-5:]},
			{n - 5, 100, data[n-5:]},
			{n, 0, nil},
			{n, 7, nil},
		} {
			r, info, err := s.OpenRange(ctx, digest, tc.offset, tc.length)
			if err != nil {
				t.Fatalf("OpenRange(%d, %d): %v", tc.offset, tc.length, err)
			}
			got, err := io.ReadAll(r)
			r.Close()
			if err != nil || !bytes.Equal(got, tc.want) || info.Size != n {
				t.Errorf("OpenRange(%d, %d) read %d bytes (%v), size %d; want %d bytes of the blob's %d", tc.offset, tc.length, len(got), err, info.Size, len(tc.want), n)
			}
		}
		if _, _, err := s.OpenRange(ctx, digest, n+1, 0); !errs.Is(err, errs.OutOfRange) {
			t.Errorf("OpenRange past the end: %v, want OutOfRange", err)
		}
		if _, _, err := s.OpenRange(ctx, rules.DigestOf([]byte("absent")), 0, 0); !errs.Is(err, errs.NotFound) {
			t.Errorf("OpenRange of an absent blob: %v, want NotFound", err)
		}
	})
}

// A range's bytes are served as stored, unchecked: a damaged blob's range reads the damage,
// and Verify, which the client asks when the assembled whole does not match the digest,
// says DataLoss.
func TestOpenRangeServesStoredBytesAndVerifyFindsTheDamage(t *testing.T) {
	forEachBackend(t, func(t *testing.T, open func(int64) (*blobstore.Store, raw)) {
		ctx := context.Background()
		s, raw := open(0)
		data := bytes.Repeat([]byte("range"), 1000)
		digest := rules.DigestOf(data)
		if _, err := s.Put(ctx, bytes.NewReader(data), int64(len(data)), digest); err != nil {
			t.Fatal(err)
		}
		damaged := bytes.Clone(data)
		damaged[100] ^= 1
		raw.write(t, digest, damaged)
		r, _, err := s.OpenRange(ctx, digest, 50, 100)
		if err != nil {
			t.Fatal(err)
		}
		got, err := io.ReadAll(r)
		r.Close()
		if err != nil || !bytes.Equal(got, damaged[50:150]) {
			t.Errorf("range of the damaged blob: %d bytes (%v), want the stored bytes", len(got), err)
		}
		if _, err := s.Verify(ctx, digest); !errs.Is(err, errs.DataLoss) {
			t.Errorf("Verify of the damaged blob: %v, want DataLoss", err)
		}
	})
}
