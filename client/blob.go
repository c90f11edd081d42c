package client

import (
	"bytes"
	"context"
	"errors"
	"fmt"
	"io"
	"io/fs"
	"os"
	"syscall"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// UploadChunkSize is the size of the chunks blobs are uploaded in: the contract's largest.
var UploadChunkSize = int(rules.RPC.GetMaxUploadChunkBytes())

// fileDigest returns the digest and size of the file at path, which must be a regular
// file of at most limit bytes (a device or a pipe could be read for ever); it stops with
// ctx's error when ctx ends.
func fileDigest(ctx context.Context, path string, limit uint64) (digest string, size int64, err error) {
	f, err := openRegular(path, limit)
	if err != nil {
		return "", 0, err
	}
	defer f.Close()
	h := rules.NewDigestHash()
	size, err = io.Copy(h, ctxReader{ctx, f})
	if err != nil {
		return "", 0, err
	}
	return rules.DigestSum(h), size, nil
}

// openRegular opens path if it is a regular file of at most limit bytes. It opens
// without blocking (a pipe's open would wait for a writer) and checks what it opened.
func openRegular(path string, limit uint64) (*os.File, error) {
	f, err := os.OpenFile(path, os.O_RDONLY|syscall.O_NONBLOCK, 0)
	if err != nil {
		return nil, err
	}
	st, err := f.Stat()
	switch {
	case err != nil:
	case !st.Mode().IsRegular():
		err = &fs.PathError{Op: "read", Path: path, Err: errors.New("not a regular file (a folder, a device or a pipe)")}
	case uint64(st.Size()) > limit:
		err = &fs.PathError{Op: "read", Path: path, Err: fmt.Errorf("%d bytes, more than the limit of %d", st.Size(), limit)}
	}
	if err != nil {
		f.Close()
		return nil, err
	}
	return f, nil
}

// readSmallFile reads a regular file (a scene file) of at most the largest message.
func readSmallFile(path string) ([]byte, error) {
	f, err := openRegular(path, rules.RPC.GetMaxMessageBytes())
	if err != nil {
		return nil, err
	}
	defer f.Close()
	return io.ReadAll(f)
}

// ctxReader reads from r until ctx ends.
type ctxReader struct {
	ctx context.Context
	r   io.Reader
}

func (c ctxReader) Read(p []byte) (int, error) {
	if err := c.ctx.Err(); err != nil {
		return 0, err
	}
	return c.r.Read(p)
}

// BlobExists reports whether the blob store holds digest intact: GetBlobInfo checks the
// stored content, and a damaged blob (DATA_LOSS) counts as absent, so that the caller
// uploads it again, which repairs it.
func (c *Client) BlobExists(ctx context.Context, digest string) (bool, error) {
	_, err := c.blobs.GetBlobInfo(ctx, &pb.GetBlobInfoRequest{Digest: digest})
	switch status.Code(err) {
	case codes.OK:
		return true, nil
	case codes.NotFound, codes.DataLoss:
		return false, nil
	}
	return false, fromRPC("blob info", err)
}

// UploadBytes stores data in the blob store, unless it is there already, and returns its
// digest.
func (c *Client) UploadBytes(ctx context.Context, data []byte) (string, error) {
	digest := rules.DigestOf(data)
	return digest, c.upload(ctx, bytes.NewReader(data), int64(len(data)), digest)
}

// UploadFile stores the file at path in the blob store, unless it is there already, and
// returns its digest. The file is read twice (to hash it, then to send it), never held in
// memory whole.
func (c *Client) UploadFile(ctx context.Context, path string) (string, error) {
	limit := rules.RPC.GetMaxBlobBytes()
	digest, size, err := fileDigest(ctx, path, limit)
	if err != nil {
		return "", err
	}
	f, err := openRegular(path, limit)
	if err != nil {
		return "", err
	}
	defer f.Close()
	return digest, c.upload(ctx, ctxReader{ctx, f}, size, digest)
}

// upload streams size bytes from r as the blob digest: a header, then chunks. It skips the
// transfer if the store already has the blob. The server checks size and digest.
func (c *Client) upload(ctx context.Context, r io.Reader, size int64, digest string) error {
	if ok, err := c.BlobExists(ctx, digest); err != nil || ok {
		return err
	}
	stream, err := c.blobs.UploadBlob(ctx)
	if err != nil {
		return fromRPC("upload blob", err)
	}
	hdr := &pb.UploadBlobRequest{Part: &pb.UploadBlobRequest_Header{
		Header: &pb.BlobHeader{SizeBytes: size, Digest: digest}}}
	if err := stream.Send(hdr); err != nil {
		_, err = stream.CloseAndRecv() // the server's reason, if it hung up
		return fromRPC("upload blob", err)
	}
	buf := make([]byte, c.chunkLen)
	var sent int64
	for sent < size {
		n, rerr := io.ReadFull(r, buf[:min(int64(len(buf)), size-sent)])
		if n > 0 {
			chunk := &pb.UploadBlobRequest{Part: &pb.UploadBlobRequest_Chunk{Chunk: buf[:n]}}
			if err := stream.Send(chunk); err != nil {
				_, err = stream.CloseAndRecv()
				return fromRPC("upload blob", err)
			}
			sent += int64(n)
		}
		if rerr != nil && sent < size {
			stream.CloseSend()
			return fmt.Errorf("upload blob %s: read: %w", digest, rerr)
		}
	}
	resp, err := stream.CloseAndRecv()
	if err != nil {
		return fromRPC("upload blob", err)
	}
	if resp.GetDigest() != digest {
		return fmt.Errorf("upload blob: the coordinator stored %s, expected %s", resp.GetDigest(), digest)
	}
	return nil
}

// Download streams the blob digest into w and checks, while streaming, that the bytes
// have that digest and the announced size. w may have received bytes when this fails, so
// callers writing files write to a temporary one and rename it on success.
func (c *Client) Download(ctx context.Context, digest string, w io.Writer) (int64, error) {
	ctx, cancel := context.WithCancel(ctx)
	defer cancel()
	stream, err := c.blobs.DownloadBlob(ctx, &pb.DownloadBlobRequest{Digest: digest})
	if err != nil {
		return 0, fromRPC("download blob", err)
	}
	h := rules.NewDigestHash()
	out := io.MultiWriter(h, w)
	var n, want int64 = 0, -1
	for {
		msg, err := stream.Recv()
		if errors.Is(err, io.EOF) {
			break
		}
		if err != nil {
			return n, fromRPC("download blob "+digest, err)
		}
		if want < 0 {
			want = msg.GetSizeBytes()
		}
		if _, err := out.Write(msg.GetChunk()); err != nil {
			return n, err
		}
		n += int64(len(msg.GetChunk()))
		if want >= 0 && n > want {
			return n, fmt.Errorf("download blob %s: more than the announced %d bytes", digest, want)
		}
	}
	if want >= 0 && n != want {
		return n, fmt.Errorf("download blob %s: got %d bytes, announced %d", digest, n, want)
	}
	if got := rules.DigestSum(h); got != digest {
		return n, fmt.Errorf("download blob %s: content has digest %s", digest, got)
	}
	return n, nil
}
