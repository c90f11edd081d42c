package service_test

import (
	"bytes"
	"crypto/rand"
	"testing"

	"google.golang.org/grpc/codes"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// DownloadBlob sends the range a request names, in chunks of at most 1 MiB, each download
// announcing the whole blob's size: ranges that tile the blob give it back, a length past
// the end stops at the end, an offset at the end sends nothing.
func TestDownloadBlobSendsTheRangeAsked(t *testing.T) {
	f := newFarm(t)
	data := make([]byte, 3<<20+5)
	rand.Read(data)
	a := f.upload(data)
	n := int64(len(data))
	for _, tc := range []struct {
		offset, length int64
		want           []byte
	}{
		{0, 0, data},
		{0, 1 << 20, data[:1<<20]},
		{1 << 20, 1<<20 + 1, data[1<<20 : 2<<20+1]},
		{2<<20 + 1, 0, data[2<<20+1:]},
		{n - 2, 1 << 30, data[n-2:]},
		{n, 0, nil},
	} {
		got, sizes, size, err := f.downloadRange(&pb.DownloadBlobRequest{Digest: a.Digest, Offset: tc.offset, Length: tc.length})
		if err != nil || !bytes.Equal(got, tc.want) || size != n {
			t.Errorf("range %d+%d: %d bytes of a blob of %d (%v); want %d bytes of %d", tc.offset, tc.length, len(got), size, err, len(tc.want), n)
		}
		for _, c := range sizes {
			if c > 1<<20 {
				t.Errorf("range %d+%d: a chunk of %d bytes, more than 1 MiB", tc.offset, tc.length, c)
			}
		}
	}
}

// A range outside the blob, or a negative offset or length, is refused naming the field.
func TestDownloadBlobRefusesBadRanges(t *testing.T) {
	f := newFarm(t)
	a := f.upload([]byte("twelve bytes"))
	for _, tc := range []struct {
		name  string
		req   *pb.DownloadBlobRequest
		code  codes.Code
		field string
	}{
		{"offset past the end", &pb.DownloadBlobRequest{Digest: a.Digest, Offset: 13}, codes.OutOfRange, "offset"},
		{"negative offset", &pb.DownloadBlobRequest{Digest: a.Digest, Offset: -1}, codes.InvalidArgument, "offset"},
		{"negative length", &pb.DownloadBlobRequest{Digest: a.Digest, Length: -5}, codes.InvalidArgument, "length"},
		{"range of a missing blob", &pb.DownloadBlobRequest{Digest: rules.DigestOf([]byte("absent")), Offset: 3}, codes.NotFound, "digest"},
	} {
		_, _, _, err := f.downloadRange(tc.req)
		wantCode(t, tc.name, err, tc.code, tc.field)
	}
}

// A whole blob asked as a range from 0 that reaches its end is checked whole first, as a
// plain download is; a range is sent as stored (the client checks what it assembles), and
// GetBlobInfo says the blob is damaged.
func TestDownloadBlobChecksWholeBlobsNotRanges(t *testing.T) {
	f := newFarm(t)
	data := bytes.Repeat([]byte("snapshot"), 1<<18) // 2 MiB
	a := f.upload(data)
	f.truncate(a.Digest)
	_, _, _, err := f.downloadRange(&pb.DownloadBlobRequest{Digest: a.Digest, Length: int64(len(data))})
	wantCode(t, "the whole damaged blob as a range from 0", err, codes.DataLoss, "")
	got, _, size, err := f.downloadRange(&pb.DownloadBlobRequest{Digest: a.Digest, Offset: 1 << 10, Length: 1 << 10})
	if err != nil || size == int64(len(data)) || !bytes.Equal(got, data[1<<10:2<<10]) {
		t.Errorf("a range of the truncated blob: %d bytes, size %d, %v; want its stored bytes", len(got), size, err)
	}
	_, err = f.blobs.GetBlobInfo(f.ctx, &pb.GetBlobInfoRequest{Digest: a.Digest})
	wantCode(t, "GetBlobInfo", err, codes.DataLoss, "")
}
