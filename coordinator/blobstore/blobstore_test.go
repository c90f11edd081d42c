package blobstore_test

import (
	"bytes"
	"context"
	"io"
	"os"
	"path/filepath"
	"strings"
	"testing"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/errs"
)

func TestPutOpenRoundTrip(t *testing.T) {
	ctx := context.Background()
	root := t.TempDir()
	s, err := blobstore.New(root, 0)
	if err != nil {
		t.Fatal(err)
	}
	data := bytes.Repeat([]byte("photon"), 100000)
	want := rules.DigestOf(data)
	info, err := s.Put(ctx, bytes.NewReader(data), int64(len(data)), want)
	if err != nil {
		t.Fatal(err)
	}
	if info.Digest != want || info.Size != int64(len(data)) {
		t.Errorf("Put = %+v", info)
	}
	hexd := strings.TrimPrefix(want, "sha256:")
	if _, err := os.Stat(filepath.Join(root, "sha256", hexd[:2], hexd)); err != nil {
		t.Errorf("blob not at its content address: %v", err)
	}
	r, got, err := s.Open(ctx, want)
	if err != nil {
		t.Fatal(err)
	}
	defer r.Close()
	b, _ := io.ReadAll(r)
	if !bytes.Equal(b, data) || got.Size != int64(len(data)) {
		t.Error("read back different bytes")
	}
	// Putting it again is fine, with or without the digest and size.
	if _, err := s.Put(ctx, bytes.NewReader(data), -1, ""); err != nil {
		t.Errorf("second Put: %v", err)
	}
	if tmp, _ := os.ReadDir(filepath.Join(root, "tmp")); len(tmp) != 0 {
		t.Errorf("temporary files left: %v", tmp)
	}
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
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			s, err := blobstore.New(t.TempDir(), 10)
			if err != nil {
				t.Fatal(err)
			}
			_, err = s.Put(context.Background(), bytes.NewReader(data), tt.size, tt.digest)
			var e *errs.Error
			if !errorsAs(err, &e) || e.Kind != tt.kind || e.Field != tt.field {
				t.Fatalf("Put = %v, want kind %v on field %s", err, tt.kind, tt.field)
			}
			if _, err := s.Stat(context.Background(), rules.DigestOf(data)); errs.KindOf(err) != errs.NotFound {
				t.Errorf("refused blob was stored: %v", err)
			}
		})
	}
	t.Run("over the limit undeclared", func(t *testing.T) {
		s, _ := blobstore.New(t.TempDir(), 3)
		_, err := s.Put(context.Background(), bytes.NewReader(data), -1, "")
		if errs.KindOf(err) != errs.ResourceExhausted {
			t.Fatalf("Put = %v, want ResourceExhausted", err)
		}
	})
}

func TestStatMissing(t *testing.T) {
	s, _ := blobstore.New(t.TempDir(), 0)
	if _, err := s.Stat(context.Background(), rules.DigestOf([]byte("x"))); errs.KindOf(err) != errs.NotFound {
		t.Errorf("Stat = %v, want NotFound", err)
	}
	if _, _, err := s.Open(context.Background(), "md5:abc"); errs.KindOf(err) != errs.InvalidArgument {
		t.Errorf("Open = %v, want InvalidArgument", err)
	}
}

// damage rewrites the stored file of digest under root with what change makes of it.
func damage(t *testing.T, root, digest string, change func([]byte) []byte) {
	t.Helper()
	path := blobstore.PathIn(root, digest)
	b, err := os.ReadFile(path)
	if err != nil {
		t.Fatal(err)
	}
	if err := os.WriteFile(path, change(b), 0o644); err != nil {
		t.Fatal(err)
	}
}

func TestDamagedBlobIsNeverReadAsIntact(t *testing.T) {
	ctx := context.Background()
	data := bytes.Repeat([]byte("photon"), 400000) // more than one read buffer
	digest := rules.DigestOf(data)
	for name, change := range map[string]func([]byte) []byte{
		"truncated":   func(b []byte) []byte { return b[:len(b)/2] },
		"one bit off": func(b []byte) []byte { b[len(b)/3] ^= 1; return b },
		"emptied":     func([]byte) []byte { return nil },
	} {
		t.Run(name, func(t *testing.T) {
			root := t.TempDir()
			s, _ := blobstore.New(root, 0)
			if _, err := s.Put(ctx, bytes.NewReader(data), int64(len(data)), digest); err != nil {
				t.Fatal(err)
			}
			if _, err := s.Verify(ctx, digest); err != nil {
				t.Fatalf("Verify of the intact blob: %v", err)
			}
			damage(t, root, digest, change)

			_, err := s.Verify(ctx, digest)
			if errs.KindOf(err) != errs.DataLoss || !strings.Contains(err.Error(), digest) {
				t.Errorf("Verify = %v, want DataLoss naming %s", err, digest)
			}
			r, _, err := s.Open(ctx, digest)
			if err != nil {
				t.Fatal(err)
			}
			defer r.Close()
			_, err = io.ReadAll(r)
			if errs.KindOf(err) != errs.DataLoss {
				t.Errorf("reading to the end = %v, want DataLoss", err)
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
}

func TestVerifyMissingIsNotFound(t *testing.T) {
	s, _ := blobstore.New(t.TempDir(), 0)
	if _, err := s.Verify(context.Background(), rules.DigestOf([]byte("x"))); errs.KindOf(err) != errs.NotFound {
		t.Errorf("Verify = %v, want NotFound", err)
	}
}
