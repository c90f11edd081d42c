package dashboard

import (
	"context"
	"encoding/json"
	"fmt"
	"net/http"
	"net/url"
	"strconv"
	"strings"
	"time"

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

// The answers to a refused request: one for every token the coordinator refuses,
// whatever the reason (unknown, another role's, malformed), so that an answer says
// nothing about which tokens exist.
const (
	msgTokenRefused = "the coordinator refused this token"
	msgNoToken      = "sign in: this request carries no token"
)

// presentsToken reports whether r carries a token, valid or not: the farm_token cookie
// or an Authorization header.
func presentsToken(r *http.Request) bool {
	if c, err := r.Cookie(CookieName); err == nil && c.Value != "" {
		return true
	}
	return r.Header.Get("Authorization") != ""
}

// refuseToken answers 401 to a request the coordinator refused; a token presented counts
// against the client's address (throttle.go).
func (s *Server) refuseToken(w http.ResponseWriter, r *http.Request, presented bool) {
	dropBody(w, r)
	if !presented {
		writeJSON(w, http.StatusUnauthorized, map[string]any{"error": msgNoToken})
		return
	}
	s.refused.refused(clientKey(r))
	writeJSON(w, http.StatusUnauthorized, map[string]any{"error": msgTokenRefused})
}

// throttled answers 429 to a client address that has had too many tokens refused.
func (s *Server) throttled(w http.ResponseWriter, r *http.Request) {
	w.Header().Set("Retry-After", strconv.Itoa(int(RefusedTokenEvery/time.Second)))
	s.writeError(w, r, errorf(http.StatusTooManyRequests,
		fmt.Sprintf("too many refused tokens from this address: try again in %v", RefusedTokenEvery)))
}

// login checks {"token": "..."} with the coordinator and sets the cookie.
func (s *Server) login(w http.ResponseWriter, r *http.Request) {
	if !s.refused.allowed(clientKey(r)) {
		s.throttled(w, r)
		return
	}
	var body struct {
		Token string `json:"token"`
	}
	if err := json.NewDecoder(r.Body).Decode(&body); err != nil {
		s.writeError(w, r, errorf(http.StatusBadRequest, "want a JSON body {\"token\": \"...\"}: "+err.Error()))
		return
	}
	if !validToken(body.Token) {
		s.refuseToken(w, r, true)
		return
	}
	ctx, cancel := context.WithTimeout(r.Context(), callTimeout)
	defer cancel()
	if err := s.check(ctx, body.Token); err != nil {
		if refused(err) {
			// A worker token is refused too (PERMISSION_DENIED): it cannot read jobs.
			s.refuseToken(w, r, true)
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
			if !authenticated {
				s.refused.refused(clientKey(r)) // a way to try tokens, too
			}
		}
	}
	writeJSON(w, http.StatusOK, map[string]any{"authenticated": authenticated, "authRequired": required})
}
