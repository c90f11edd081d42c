package blobstore_test

import (
	"bytes"
	"context"
	"errors"
	"io"
	"net"
	"strings"
	"testing"
	"time"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/blobstore/s3test"
	"photonfarm/coordinator/errs"
	"photonfarm/tests/tcpproxy"
)

func TestOpenRefusesBadURLs(t *testing.T) {
	srv := s3test.Shared(t)
	closed, err := net.Listen("tcp", "127.0.0.1:0")
	if err != nil {
		t.Fatal(err)
	}
	closed.Close()
	tests := []struct {
		name, url string
		want      []string // in the error
		notWant   string   // never in it
	}{
		{"credentials in the URL", "s3://AKIA:hunter2@farm?endpoint=" + srv.Endpoint, []string{"credentials in the URL are refused", "AWS_ACCESS_KEY_ID"}, "hunter2"},
		{"relative folder", "file://blobs", []string{"absolute folder"}, ""},
		{"unknown scheme", "gs://farm", []string{"scheme must be file or s3"}, ""},
		{"bad stall timeout", srv.URL("") + "&stall_timeout=soon", []string{"stall_timeout must be a positive duration", `"soon"`}, ""},
		{"no such bucket", strings.Replace(srv.URL(""), "s3://"+s3test.Bucket, "s3://no-such-bucket", 1), []string{"no-such-bucket"}, ""},
		{"nothing listening", s3test.URL("http://"+closed.Addr().String(), "") + "&stall_timeout=2s", []string{"object store", closed.Addr().String()}, ""},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			ctx, cancel := context.WithTimeout(context.Background(), 30*time.Second)
			defer cancel()
			s, err := blobstore.Open(ctx, tt.url, 0)
			if err == nil {
				s.Close()
				t.Fatalf("Open(%s) succeeded", tt.url)
			}
			t.Log(err)
			for _, w := range tt.want {
				if !strings.Contains(err.Error(), w) {
					t.Errorf("Open = %v, want it to say %q", err, w)
				}
			}
			if tt.notWant != "" && strings.Contains(err.Error(), tt.notWant) {
				t.Errorf("Open = %v: it shows %q", err, tt.notWant)
			}
		})
	}
}

func TestOpenFileURLIsTheFolderStore(t *testing.T) {
	root := t.TempDir()
	s, err := blobstore.Open(context.Background(), "file://"+root, 0)
	if err != nil {
		t.Fatal(err)
	}
	info, err := s.Put(context.Background(), strings.NewReader("x"), 1, "")
	if err != nil {
		t.Fatal(err)
	}
	f, _ := blobstore.New(root, 0)
	if _, err := f.Verify(context.Background(), info.Digest); err != nil {
		t.Errorf("the blob is not in the folder %s: %v", root, err)
	}
}

// TestAStoreThatStopsAnsweringFailsWithinTheStallTimeout: the object store frozen
// mid-read, mid-upload and before a call (a proxy in front of the server passes
// nothing): each call ends within the stall timeout as unavailable, naming the store and
// saying it got no answer, and works again once the store answers.
func TestAStoreThatStopsAnsweringFailsWithinTheStallTimeout(t *testing.T) {
	srv := s3test.Shared(t)
	proxy := tcpproxy.New(t, srv.Host())
	const stall = 2 * time.Second
	s, err := blobstore.Open(context.Background(), s3test.URL("http://"+proxy.Addr, "stall/")+"&stall_timeout="+stall.String(), 0)
	if err != nil {
		t.Fatal(err)
	}
	defer s.Close()
	ctx := context.Background()
	data := bytes.Repeat([]byte("stall"), 2<<20) // 10 MiB: the read is under way when it freezes
	info, err := s.Put(ctx, bytes.NewReader(data), int64(len(data)), "")
	if err != nil {
		t.Fatal(err)
	}
	check := func(what string, err error, start time.Time) {
		t.Helper()
		t.Logf("%s after %v: %v", what, time.Since(start).Round(time.Millisecond), err)
		if took := time.Since(start); took > 3*stall {
			t.Errorf("%s took %v, want about the stall timeout %v", what, took, stall)
		}
		if errs.KindOf(err) != errs.Unavailable || !strings.Contains(err.Error(), "object store s3://"+s3test.Bucket) ||
			!strings.Contains(err.Error(), "got no answer for "+stall.String()) {
			t.Errorf("%s = %v, want unavailable naming the store and the stall", what, err)
		}
	}

	r, _, err := s.Open(ctx, info.Digest)
	if err != nil {
		t.Fatal(err)
	}
	if _, err := r.Read(make([]byte, 1024)); err != nil {
		t.Fatal(err)
	}
	proxy.Freeze()
	start := time.Now()
	_, err = blobstore.ReadAll(r, info.Size)
	check("a read", err, start)
	r.Close()

	start = time.Now()
	_, err = s.Put(ctx, bytes.NewReader(data[:1000]), 1000, "")
	check("an upload", err, start)

	start = time.Now()
	_, err = s.Stat(ctx, info.Digest)
	check("a stat", err, start)

	proxy.Thaw()
	if _, err := s.Verify(ctx, info.Digest); err != nil {
		t.Errorf("Verify once the store answers again: %v", err)
	}
	if _, err := s.Stat(ctx, rules.DigestOf(data[:1000])); errs.KindOf(err) != errs.NotFound {
		t.Errorf("the upload cut off by the stall was stored: %v", err)
	}
}

// TestAConnectionCutMidReadIsUnavailableNotTheEndOfTheBlob: the store's connection
// closed mid-body (the server died) is an unavailable store, and nothing in the error
// says end of file: a reader of a shard would take that for a truncated file, bad input.
func TestAConnectionCutMidReadIsUnavailableNotTheEndOfTheBlob(t *testing.T) {
	srv := s3test.Shared(t)
	proxy := tcpproxy.New(t, srv.Host())
	s, err := blobstore.Open(context.Background(), s3test.URL("http://"+proxy.Addr, "cut/"), 0)
	if err != nil {
		t.Fatal(err)
	}
	defer s.Close()
	ctx := context.Background()
	data := bytes.Repeat([]byte("cut"), 4<<20) // 12 MiB: far more than one read
	info, err := s.Put(ctx, bytes.NewReader(data), int64(len(data)), "")
	if err != nil {
		t.Fatal(err)
	}
	r, _, err := s.Open(ctx, info.Digest)
	if err != nil {
		t.Fatal(err)
	}
	defer r.Close()
	if _, err := io.ReadFull(r, make([]byte, 1<<20)); err != nil {
		t.Fatal(err)
	}
	proxy.Cut()
	_, err = io.ReadAll(r)
	t.Log(err)
	if errs.KindOf(err) != errs.Unavailable || errors.Is(err, io.EOF) || errors.Is(err, io.ErrUnexpectedEOF) {
		t.Errorf("reading on after the cut = %v, want unavailable and no end of file in it", err)
	}
}
