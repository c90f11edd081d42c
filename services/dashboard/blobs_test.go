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
