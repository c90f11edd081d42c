package dashboard

import (
	"errors"
	"io"
	"net/http"
	"path"
	"strconv"
	"strings"

	pb "photonfarm/proto/renderfarm/v1"
)

// contentTypes by the extension of the artifact's name; others are
// application/octet-stream.
var contentTypes = map[string]string{
	".png":  "image/png",
	".exr":  "image/x-exr",
	".json": "application/json",
	".txt":  "text/plain; charset=utf-8",
	".log":  "text/plain; charset=utf-8", // a task's log ("task.log")
}

func contentTypeOf(name string) string {
	if t, ok := contentTypes[strings.ToLower(path.Ext(name))]; ok {
		return t
	}
	return "application/octet-stream"
}

// blob streams a blob from the coordinator (DownloadBlob). Blobs are content-addressed,
// so the answer never changes: the browser may keep it (privately: it needed a token).
func (s *Server) blob(w http.ResponseWriter, r *http.Request) {
	digest := r.PathValue("digest")
	etag := `"` + digest + `"`
	if match := r.Header.Get("If-None-Match"); match != "" && match == etag {
		w.WriteHeader(http.StatusNotModified)
		return
	}
	ctx, cancel := callCtx(r)
	defer cancel()
	stream, err := s.blobs.DownloadBlob(ctx, &pb.DownloadBlobRequest{Digest: digest})
	if err != nil {
		s.writeError(w, r, err)
		return
	}
	// The first message says whether the blob exists (and its size): only then are the
	// headers written, so that a missing blob is a 404 rather than an empty 200.
	first, err := stream.Recv()
	if errors.Is(err, io.EOF) {
		first, err = &pb.DownloadBlobResponse{}, nil
	}
	if err != nil {
		s.writeError(w, r, err)
		return
	}
	h := w.Header()
	h.Set("Content-Type", contentTypeOf(r.URL.Query().Get("name")))
	h.Set("Content-Length", strconv.FormatInt(first.GetSizeBytes(), 10))
	h.Set("Cache-Control", "private, max-age=31536000, immutable")
	h.Set("ETag", etag)
	w.WriteHeader(http.StatusOK)
	if r.Method == http.MethodHead {
		return
	}
	if _, err := w.Write(first.GetChunk()); err != nil {
		return
	}
	for {
		msg, err := stream.Recv()
		if errors.Is(err, io.EOF) {
			return
		}
		if err != nil {
			// Too late for a status: cut the connection, so that the browser sees a
			// broken transfer rather than caching a short image.
			s.log.Warn("dashboard blob download broke", "digest", digest, "err", err)
			panic(http.ErrAbortHandler)
		}
		if _, err := w.Write(msg.GetChunk()); err != nil {
			return
		}
	}
}
