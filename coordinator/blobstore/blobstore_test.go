package blobstore_test

import (
	"bytes"
	"context"
	"io"
	"strings"
	"testing"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/errs"
)

// The conformance suite: every test here runs on every backend (backends_test.go).

func TestPutOpenRoundTrip(t *testing.T) {
	forEachBackend(t, func(t *testing.T, open func(int64) (*blobstore.Store, raw)) {
		ctx := context.Background()
		s, raw := open(0)
		data := bytes.Repeat([]byte("photon"), 1<<20) // 6 MiB: more than one upload part
		want := rules.DigestOf(data)
		info, err := s.Put(ctx, bytes.NewReader(data), int64(len(data)), want)
		if err != nil {
			t.Fatal(err)
		}
		if info.Digest != want || info.Size != int64(len(data)) {
			t.Errorf("Put = %+v", info)
		}
		if !bytes.Equal(raw.read(t, want), data) {
			t.Error("the blob is not at its content address")
		}
		r, got, err := s.Open(ctx, want)
		if err != nil {
			t.Fatal(err)
		}
		defer r.Close()
		b, err := io.ReadAll(r)
		if err != nil || !bytes.Equal(b, data) || got.Size != int64(len(data)) {
			t.Errorf("read back %d bytes (%v), want the %d put", len(b), err, len(data))
		}
		// Putting it again is fine, with or without the digest and size.
		if _, err := s.Put(ctx, bytes.NewReader(data), -1, ""); err != nil {
			t.Errorf("second Put: %v", err)
		}
		small := []byte("undeclared")
		if info, err := s.Put(ctx, bytes.NewReader(small), -1, ""); err != nil || info.Digest != rules.DigestOf(small) {
			t.Errorf("Put without a digest = %+v, %v", info, err)
		}
		if left := raw.leftovers(t); len(left) != 0 {
			t.Errorf("temporary files left: %v", left)
		}
	})
}

func TestPutRefuses(t *testing.T) {
	data := []byte("hello")
	other := rules.DigestOf([]byte("other"))
	tests := []struct {
		name   string
		size   int64
		digest string
		kind   errs.Kind
		field  string
	}{
		{"wrong digest", 5, other, errs.InvalidArgument, "digest"},
		{"malformed digest", 5, "sha256:XYZ", errs.InvalidArgument, "digest"},
		{"short", 6, "", errs.InvalidArgument, "size_bytes"},
		{"long", 4, "", errs.InvalidArgument, "size_bytes"},
		{"over the limit declared", 11, "", errs.ResourceExhausted, "size_bytes"},
	}
	forEachBackend(t, func(t *testing.T, open func(int64) (*blobstore.Store, raw)) {
		s, raw := open(10)
		for _, tt := range tests {
			t.Run(tt.name, func(t *testing.T) {
				_, err := s.Put(context.Background(), bytes.NewReader(data), tt.size, tt.digest)
				var e *errs.Error
				if !errorsAs(err, &e) || e.Kind != tt.kind || e.Field != tt.field {
					t.Fatalf("Put = %v, want kind %v on field %s", err, tt.kind, tt.field)
				}
				for _, d := range []string{rules.DigestOf(data), other} {
					if _, err := s.Stat(context.Background(), d); errs.KindOf(err) != errs.NotFound {
						t.Errorf("refused blob was stored as %s: %v", d, err)
					}
				}
			})
		}
		t.Run("over the limit undeclared", func(t *testing.T) {
			s, _ := open(3)
			_, err := s.Put(context.Background(), bytes.NewReader(data), -1, "")
			if errs.KindOf(err) != errs.ResourceExhausted {
				t.Fatalf("Put = %v, want ResourceExhausted", err)
			}
		})
		if left := raw.leftovers(t); len(left) != 0 {
			t.Errorf("refused uploads left: %v", left)
		}
	})
}

func TestStatMissing(t *testing.T) {
	forEachBackend(t, func(t *testing.T, open func(int64) (*blobstore.Store, raw)) {
		s, _ := open(0)
		ctx := context.Background()
		missing := rules.DigestOf([]byte("x"))
		if _, err := s.Stat(ctx, missing); errs.KindOf(err) != errs.NotFound {
			t.Errorf("Stat = %v, want NotFound", err)
		}
		if _, _, err := s.Open(ctx, missing); errs.KindOf(err) != errs.NotFound {
			t.Errorf("Open = %v, want NotFound", err)
		}
		if _, err := s.Verify(ctx, missing); errs.KindOf(err) != errs.NotFound {
			t.Errorf("Verify = %v, want NotFound", err)
		}
		if _, _, err := s.Open(ctx, "md5:abc"); errs.KindOf(err) != errs.InvalidArgument {
			t.Errorf("Open = %v, want InvalidArgument", err)
		}
	})
}

func TestDamagedBlobIsNeverReadAsIntact(t *testing.T) {
	data := bytes.Repeat([]byte("photon"), 400000) // more than one read buffer
	digest := rules.DigestOf(data)
	changes := []struct {
		name   string
		change func([]byte) []byte
	}{
		{"truncated", func(b []byte) []byte { return b[:len(b)/2] }},
		{"one bit off", func(b []byte) []byte { b[len(b)/3] ^= 1; return b }},
		{"emptied", func([]byte) []byte { return nil }},
	}
	forEachBackend(t, func(t *testing.T, open func(int64) (*blobstore.Store, raw)) {
		ctx := context.Background()
		for _, c := range changes {
			t.Run(c.name, func(t *testing.T) {
				s, raw := open(0)
				if _, err := s.Put(ctx, bytes.NewReader(data), int64(len(data)), digest); err != nil {
					t.Fatal(err)
				}
				if _, err := s.Verify(ctx, digest); err != nil {
					t.Fatalf("Verify of the intact blob: %v", err)
				}
				raw.write(t, digest, c.change(raw.read(t, digest)))

				_, err := s.Verify(ctx, digest)
				if errs.KindOf(err) != errs.DataLoss || !strings.Contains(err.Error(), digest) {
					t.Errorf("Verify = %v, want DataLoss naming %s", err, digest)
				}
				r, info, err := s.Open(ctx, digest)
				if err != nil {
					t.Fatal(err)
				}
				defer r.Close()
				if _, err = blobstore.ReadAll(r, info.Size); errs.KindOf(err) != errs.DataLoss || !strings.Contains(err.Error(), digest) {
					t.Errorf("reading it whole = %v, want DataLoss naming %s", err, digest)
				}
				// Uploading the blob again repairs it.
				if _, err := s.Put(ctx, bytes.NewReader(data), int64(len(data)), digest); err != nil {
					t.Fatal(err)
				}
				if _, err := s.Verify(ctx, digest); err != nil {
					t.Errorf("Verify after uploading again: %v", err)
				}
			})
		}
	})
}
