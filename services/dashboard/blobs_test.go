package dashboard_test

import (
	"bytes"
	"net/http"
	"os"
	"path/filepath"
	"strings"
	"testing"

	"photonfarm/coordinator/blobstore"
)

// A blob damaged in the coordinator's store is an error, never its bytes with a header
// that lets the browser keep them for a year.
func TestBlobProxyNeverServesADamagedBlob(t *testing.T) {
	dir := t.TempDir()
	f := newFarm(t, dataDir(dir))
	b := f.browser(clientToken)
	data := bytes.Repeat([]byte("\x89PNG tile "), 300000) // several download chunks
	digest, err := f.c.UploadBytes(f.ctx, data)
	must(t, err)
	small, err := f.c.UploadBytes(f.ctx, []byte("\x89PNG small"))
	must(t, err)
	for _, d := range []string{digest, small} {
		path := blobstore.PathIn(filepath.Join(dir, "blobs"), d)
		st, err := os.Stat(path)
		must(t, err)
		must(t, os.Truncate(path, st.Size()-1))

		r := f.do(b, "GET", "/api/blobs/"+d+"?name=tile.png", "")
		wantStatus(t, "damaged blob", r, http.StatusBadGateway)
		if cc := r.Header.Get("Cache-Control"); strings.Contains(cc, "immutable") || r.Header.Get("ETag") != "" {
			t.Errorf("damaged blob: Cache-Control %q, ETag %q; want neither", cc, r.Header.Get("ETag"))
		}
		if !strings.Contains(r.Body, d+" is damaged") {
			t.Errorf("damaged blob: body %q, want it to say which blob is damaged", r.Body)
		}
	}
}

// A blob is served with the content type of its name's extension, never sniffed: a task's
// log is plain UTF-8 text even when it holds markup.
func TestBlobProxyContentTypeFollowsTheName(t *testing.T) {
	f := newFarm(t)
	b := f.browser(clientToken)
	log := "time=2026-12-02T18:00:00.000Z level=WARN msg=\"task failed\" error=\"<script>alert(1)</script> é\"\n"
	digest, err := f.c.UploadBytes(f.ctx, []byte(log))
	must(t, err)
	for _, tt := range []struct{ name, want string }{
		{"task.log", "text/plain; charset=utf-8"},
		{"tile.png", "image/png"},
		{"image.exr", "image/x-exr"},
		{"photons.shard", "application/octet-stream"},
	} {
		r := f.do(b, "GET", "/api/blobs/"+digest+"?name="+tt.name, "")
		wantStatus(t, tt.name, r, http.StatusOK)
		if got := r.Header.Get("Content-Type"); got != tt.want {
			t.Errorf("%s: Content-Type %q, want %q", tt.name, got, tt.want)
		}
		if got := r.Header.Get("X-Content-Type-Options"); got != "nosniff" {
			t.Errorf("%s: X-Content-Type-Options %q, want nosniff", tt.name, got)
		}
		if r.Body != log {
			t.Errorf("%s: body %q, want the blob's bytes", tt.name, r.Body)
		}
	}
}
