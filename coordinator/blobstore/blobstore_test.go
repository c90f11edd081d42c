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
