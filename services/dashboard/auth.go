package dashboard

import (
	"context"
	"encoding/json"
	"net/http"
	"net/url"
	"strings"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/client"
	pb "photonfarm/proto/renderfarm/v1"
)

// CookieName is the cookie holding the browser's coordinator client token.
const CookieName = "farm_token"

// tokenOf returns the token a request carries: the farm_token cookie, else an
// Authorization: Bearer header; "" if neither or if it could not be a token (the
// coordinator then refuses the calls as unauthenticated).
func tokenOf(r *http.Request) string {
	t := ""
	if c, err := r.Cookie(CookieName); err == nil && c.Value != "" {
		// The value is query-escaped (login); a token pasted into the cookie by hand is
		// taken as it is if it does not unescape.
		var err error
		if t, err = url.QueryUnescape(c.Value); err != nil {
			t = c.Value
		}
	} else if h := r.Header.Get("Authorization"); len(h) > 7 && strings.EqualFold(h[:7], "Bearer ") {
		t = strings.TrimSpace(h[7:])
	}
	if !validToken(t) {
		return ""
	}
	return t
}

// validToken reports whether t can travel as gRPC metadata: printable ASCII without
// spaces, as every coordinator token is (coordinator/auth).
func validToken(t string) bool {
	for i := 0; i < len(t); i++ {
		if t[i] <= ' ' || t[i] > '~' {
			return false
		}
	}
	return len(t) <= 4096
}

// callCtx is the context of a request's calls to the coordinator: the request's, with its
// token, bounded by callTimeout.
func callCtx(r *http.Request) (context.Context, context.CancelFunc) {
	return context.WithTimeout(client.ContextWithToken(r.Context(), tokenOf(r)), callTimeout)
}

// check asks the coordinator whether token may read jobs (a ListJobs of one job).
func (s *Server) check(ctx context.Context, token string) error {
	_, err := s.jobs.ListJobs(client.ContextWithToken(ctx, token), &pb.ListJobsRequest{PageSize: 1})
	return err
}

func refused(err error) bool {
	c := status.Code(err)
	return c == codes.Unauthenticated || c == codes.PermissionDenied
}

// login checks {"token": "..."} with the coordinator and sets the cookie.
func (s *Server) login(w http.ResponseWriter, r *http.Request) {
	var body struct {
		Token string `json:"token"`
	}
	if err := json.NewDecoder(r.Body).Decode(&body); err != nil {
		s.writeError(w, r, errorf(http.StatusBadRequest, "want a JSON body {\"token\": \"...\"}: "+err.Error()))
		return
	}
	if !validToken(body.Token) {
		s.writeError(w, r, errorf(http.StatusUnauthorized, "not a token: tokens are printable ASCII without spaces"))
		return
	}
	ctx, cancel := context.WithTimeout(r.Context(), callTimeout)
	defer cancel()
	if err := s.check(ctx, body.Token); err != nil {
		if refused(err) {
			// A worker token is refused too (PERMISSION_DENIED): it cannot read jobs.
			s.writeError(w, r, errorf(http.StatusUnauthorized, status.Convert(err).Message()))
			return
		}
		s.writeError(w, r, err)
		return
	}
	http.SetCookie(w, &http.Cookie{
		Name:     CookieName,
		Value:    url.QueryEscape(body.Token),
		Path:     "/",
		HttpOnly: true,
		SameSite: http.SameSiteStrictMode,
		Secure:   r.TLS != nil,
	})
	writeJSON(w, http.StatusOK, map[string]any{"ok": true})
}

// logout clears the cookie.
func (s *Server) logout(w http.ResponseWriter, r *http.Request) {
	http.SetCookie(w, &http.Cookie{
		Name:     CookieName,
		Value:    "",
		Path:     "/",
		MaxAge:   -1,
		HttpOnly: true,
		SameSite: http.SameSiteStrictMode,
		Secure:   r.TLS != nil,
	})
	writeJSON(w, http.StatusOK, map[string]any{"ok": true})
}

// session says whether the request's token (if any) is accepted and whether the
// coordinator wants one at all.
func (s *Server) session(w http.ResponseWriter, r *http.Request) {
	ctx, cancel := context.WithTimeout(r.Context(), callTimeout)
	defer cancel()
	required := false
	if err := s.check(ctx, ""); refused(err) {
		required = true
	} else if err != nil {
		s.writeError(w, r, err)
		return
	}
	authenticated := !required
	if required {
		if t := tokenOf(r); t != "" {
			err := s.check(ctx, t)
			if err != nil && !refused(err) {
				s.writeError(w, r, err)
				return
			}
			authenticated = err == nil
		}
	}
	writeJSON(w, http.StatusOK, map[string]any{"authenticated": authenticated, "authRequired": required})
}
