package service_test

import (
	"bytes"
	"crypto/rand"
	"testing"

	"google.golang.org/grpc/codes"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/blobstore"
	pb "photonfarm/proto/renderfarm/v1"
)

func TestBlobRoundTrip(t *testing.T) {
	f := newFarm(t)
	data := make([]byte, 5<<20+123)
	rand.Read(data)
	digest := rules.DigestOf(data)
	resp, err := f.uploadChunks(&pb.BlobHeader{SizeBytes: int64(len(data)), Digest: digest}, chunks(data, 4<<20)...)
	if err != nil || resp.Digest != digest || resp.SizeBytes != int64(len(data)) {
		t.Fatalf("UploadBlob = %v, %v", resp, err)
	}
	got, sizes, err := f.download(digest)
	if err != nil || !bytes.Equal(got, data) {
		t.Fatalf("DownloadBlob: %v (equal %v)", err, bytes.Equal(got, data))
	}
	for _, n := range sizes {
		if n > 1<<20 {
			t.Errorf("download chunk of %d bytes, want at most 1 MiB", n)
		}
	}
	info, err := f.blobs.GetBlobInfo(f.ctx, &pb.GetBlobInfoRequest{Digest: digest})
	if err != nil || info.SizeBytes != int64(len(data)) {
		t.Errorf("GetBlobInfo = %v, %v", info, err)
	}
	// Uploading it again succeeds; so does an empty blob without a digest.
	if _, err := f.uploadChunks(&pb.BlobHeader{SizeBytes: int64(len(data))}, chunks(data, 1<<20)...); err != nil {
		t.Errorf("second upload: %v", err)
	}
	empty, err := f.uploadChunks(&pb.BlobHeader{})
	if err != nil || empty.Digest != rules.DigestOf(nil) {
		t.Fatalf("empty upload = %v, %v", empty, err)
	}
	if got, _, err := f.download(empty.Digest); err != nil || len(got) != 0 {
		t.Errorf("empty download = %d bytes, %v", len(got), err)
	}
}

func TestUploadRefusesBadBlobs(t *testing.T) {
	f := newFarm(t)
	data := []byte("the bytes of a tile")
	tests := []struct {
		name   string
		header *pb.BlobHeader
		chunks [][]byte
		code   codes.Code
		field  string
	}{
		{"corrupted digest", &pb.BlobHeader{SizeBytes: int64(len(data)), Digest: rules.DigestOf([]byte("other bytes"))}, [][]byte{data}, codes.InvalidArgument, "header.digest"},
		{"malformed digest", &pb.BlobHeader{SizeBytes: int64(len(data)), Digest: "sha1:abc"}, [][]byte{data}, codes.InvalidArgument, "header.digest"},
		{"fewer bytes than declared", &pb.BlobHeader{SizeBytes: int64(len(data)) + 1}, [][]byte{data}, codes.InvalidArgument, "header.size_bytes"},
		{"more bytes than declared", &pb.BlobHeader{SizeBytes: 3}, [][]byte{data}, codes.InvalidArgument, "header.size_bytes"},
		{"negative size", &pb.BlobHeader{SizeBytes: -1}, nil, codes.InvalidArgument, "header.size_bytes"},
		{"over the size limit", &pb.BlobHeader{SizeBytes: blobstore.DefaultMaxSize + 1}, nil, codes.ResourceExhausted, "header.size_bytes"},
		{"chunk over 4 MiB", &pb.BlobHeader{SizeBytes: 5 << 20}, [][]byte{make([]byte, 5<<20)}, codes.InvalidArgument, "chunk"},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			_, err := f.uploadChunks(tt.header, tt.chunks...)
			wantCode(t, "UploadBlob", err, tt.code, tt.field)
		})
	}
	if n := f.blobCount(); n != 0 {
		t.Errorf("%d refused blobs were stored", n)
	}
	stream, _ := f.blobs.UploadBlob(f.ctx)
	stream.Send(&pb.UploadBlobRequest{Part: &pb.UploadBlobRequest_Chunk{Chunk: data}})
	_, err := stream.CloseAndRecv()
	wantCode(t, "chunk before header", err, codes.InvalidArgument, "header")

	_, _, err = f.download(rules.DigestOf([]byte("never uploaded")))
	wantCode(t, "download missing", err, codes.NotFound, "digest")
	_, _, err = f.download("")
	wantCode(t, "download no digest", err, codes.InvalidArgument, "digest")
	_, err = f.blobs.GetBlobInfo(f.ctx, &pb.GetBlobInfoRequest{Digest: "sha256:nothex"})
	wantCode(t, "info malformed", err, codes.InvalidArgument, "digest")
}
