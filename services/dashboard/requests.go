package dashboard

import (
	"context"
	"mime"
	"net/http"

	"photonfarm/contract/rules"
)

// Request body limits by endpoint (API.md, docs/limits.md).
const (
	// MaxSmallBody limits the bodies of login ({"token": ...}; a token is at most 4096
	// bytes), logout, cancel and priority.
	MaxSmallBody = 8 << 10
)

// MaxSceneBody limits POST /api/jobs (a scene with inline meshes): as large as a gRPC
// message may be. Such a body is read only once the coordinator has accepted the
// request's token.
var MaxSceneBody = int64(rules.RPC.GetMaxMessageBytes())

// crossOrigin refuses state-changing requests that a browser sent from another origin,
// another port of the same host included (such a page is "same-site", so SameSite=Strict
// cookies alone do not stop it): Sec-Fetch-Site must say same-origin, or without it the
// Origin header, when there is one, must name the host the request was sent to.
var crossOrigin = http.NewCrossOriginProtection()

// jsonPost is h behind the checks of a state-changing endpoint: a JSON body (a page of
// another origin cannot send one without a CORS preflight, which the dashboard never
// grants; a form can only send text/plain, urlencoded or multipart bodies) of at most
// limit bytes.
func (s *Server) jsonPost(limit int64, h http.HandlerFunc) http.HandlerFunc {
	return func(w http.ResponseWriter, r *http.Request) {
		if mt, _, err := mime.ParseMediaType(r.Header.Get("Content-Type")); err != nil || mt != "application/json" {
			s.writeError(w, r, errorf(http.StatusUnsupportedMediaType, "want a JSON body: Content-Type: application/json"))
			return
		}
		r.Body = http.MaxBytesReader(w, r.Body, limit)
		h(w, r)
	}
}

// signedIn is h once the coordinator has accepted the request's token, checked before
// anything of the body is read: a request without a valid token costs its headers only.
func (s *Server) signedIn(h http.HandlerFunc) http.HandlerFunc {
	return func(w http.ResponseWriter, r *http.Request) {
		ctx, cancel := context.WithTimeout(r.Context(), callTimeout)
		defer cancel()
		if err := s.check(ctx, tokenOf(r)); err != nil {
			s.writeError(w, r, err)
			return
		}
		h(w, r)
	}
}
