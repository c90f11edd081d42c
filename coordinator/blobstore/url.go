package blobstore

import (
	"context"
	"fmt"
	"net/url"
	"path/filepath"
	"time"

	"gocloud.dev/blob"
	"gocloud.dev/blob/s3blob"
)

// DefaultStallTimeout is how long one call on an object store may go without an answer
// before it fails as unavailable (s3://...&stall_timeout=).
const DefaultStallTimeout = 30 * time.Second

// Open opens the blob store a URL names (maxSize <= 0 selects DefaultMaxSize):
//
//	file:///abs/folder
//	    a folder on this machine (New).
//	s3://BUCKET?endpoint=URL&region=REGION[&use_path_style=true][&prefix=P/][&stall_timeout=30s]
//	    an S3-compatible object store (AWS S3, SeaweedFS, Ceph, ...) through
//	    gocloud.dev/blob/s3blob, with its other query parameters (disable_https, profile,
//	    ...); prefix puts every key under P/, so that farms can share a bucket.
//
// An s3:// store's credentials are the AWS SDK's usual ones, never the URL's:
// AWS_ACCESS_KEY_ID and AWS_SECRET_ACCESS_KEY, or a credentials file
// (AWS_SHARED_CREDENTIALS_FILE, with profile= or AWS_PROFILE), or the platform's role. A
// URL with a user or password is refused, as it would show in logs and process lists.
// Open checks the bucket answers, so that a wrong endpoint, bucket or credentials stop
// the coordinator at start rather than its first upload.
func Open(ctx context.Context, rawURL string, maxSize int64) (*Store, error) {
	u, err := url.Parse(rawURL)
	if err != nil {
		return nil, fmt.Errorf("blob store URL: %w", err)
	}
	if u.User != nil {
		return nil, fmt.Errorf("blob store URL %s://%s: credentials in the URL are refused (they would show in logs); "+
			"give them as AWS_ACCESS_KEY_ID and AWS_SECRET_ACCESS_KEY or in AWS_SHARED_CREDENTIALS_FILE", u.Scheme, u.Host)
	}
	switch u.Scheme {
	case "file":
		if u.Host != "" || !filepath.IsAbs(u.Path) {
			return nil, fmt.Errorf("blob store URL %q: a file URL names an absolute folder, file:///path", rawURL)
		}
		return New(u.Path, maxSize)
	case s3blob.Scheme:
		b, err := openBucket(ctx, u)
		if err != nil {
			return nil, err
		}
		return newStore(b, maxSize), nil
	}
	return nil, fmt.Errorf("blob store URL %q: the scheme must be file or s3", rawURL)
}

func openBucket(ctx context.Context, u *url.URL) (*bucketBackend, error) {
	q := u.Query()
	stall := DefaultStallTimeout
	if s := q.Get("stall_timeout"); s != "" {
		d, err := time.ParseDuration(s)
		if err != nil || d <= 0 {
			return nil, fmt.Errorf("blob store URL %s://%s: stall_timeout must be a positive duration such as 30s, got %q", u.Scheme, u.Host, s)
		}
		stall = d
		q.Del("stall_timeout")
	}
	name := u.Scheme + "://" + u.Host + "/" + q.Get("prefix")
	if e := q.Get("endpoint"); e != "" {
		name += " at " + e
	}
	u.RawQuery = q.Encode()
	bucket, err := blob.OpenBucket(ctx, u.String())
	if err != nil {
		return nil, fmt.Errorf("object store %s: %w", name, err)
	}
	b := &bucketBackend{b: bucket, name: name, stall: stall}
	var ok bool
	err = b.do(ctx, "check", "the bucket", func(ctx context.Context) (err error) {
		ok, err = bucket.IsAccessible(ctx)
		return err
	})
	if err == nil && !ok {
		err = fmt.Errorf("object store %s: the bucket %s does not exist", name, u.Host)
	}
	if err != nil {
		bucket.Close()
		return nil, err
	}
	return b, nil
}
