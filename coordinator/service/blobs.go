package service

import (
	"context"
	"errors"
	"io"

	"photonfarm/contract/rules"
	"photonfarm/coordinator/blobstore"
	"photonfarm/coordinator/errs"
	pb "photonfarm/proto/renderfarm/v1"
)

type blobServer struct {
	pb.UnimplementedBlobServiceServer
	s *Service
}

var _ pb.BlobServiceServer = (*blobServer)(nil)

func checkDigest(d string) error {
	if d == "" {
		return errs.Field("digest", "must be non-empty")
	}
	if !rules.ValidDigest(d) {
		return errs.Field("digest", "must be \"sha256:\" followed by 64 lowercase hex digits, got %q", d)
	}
	return nil
}

// UploadBlob receives a header then chunks, verifying size and digest before the blob
// becomes visible.
func (b *blobServer) UploadBlob(stream pb.BlobService_UploadBlobServer) error {
	first, err := stream.Recv()
	if errors.Is(err, io.EOF) {
		return errs.Field("header", "the upload ended before its header")
	}
	if err != nil {
		return err
	}
	h := first.GetHeader()
	if h == nil {
		return errs.Field("header", "the first message must be the header")
	}
	if h.GetSizeBytes() < 0 {
		return errs.Field("header.size_bytes", "must be >= 0, got %d", h.GetSizeBytes())
	}
	if d := h.GetDigest(); d != "" && !rules.ValidDigest(d) {
		return errs.Field("header.digest", "must be \"sha256:\" followed by 64 lowercase hex digits, got %q", d)
	}
	w, err := b.s.cfg.Blobs.Create(stream.Context(), h.GetSizeBytes(), h.GetDigest())
	if err != nil {
		return inHeader(err)
	}
	defer w.Abort()
	for {
		msg, err := stream.Recv()
		if errors.Is(err, io.EOF) {
			break
		}
		if err != nil {
			return err
		}
		if msg.GetHeader() != nil {
			return errs.Field("header", "sent twice; only the first message is a header")
		}
		if n := uint64(len(msg.GetChunk())); n > rules.RPC.GetMaxUploadChunkBytes() {
			return errs.Field("chunk", "%d bytes exceeds the %d byte chunk limit", n, rules.RPC.GetMaxUploadChunkBytes())
		}
		if _, err := w.Write(msg.GetChunk()); err != nil {
			return inHeader(err)
		}
	}
	info, err := w.Commit()
	if err != nil {
		return inHeader(err)
	}
	b.s.log.Debug("blob stored", "digest", info.Digest, "size", info.Size)
	return stream.SendAndClose(&pb.UploadBlobResponse{Digest: info.Digest, SizeBytes: info.Size})
}

// DownloadBlob streams a blob, or the range of it the request names, in chunks of the
// contract's download chunk size. A whole blob is verified whole first, so that a damaged
// one is an error before any byte (a browser behind the dashboard would show the start of
// a broken image), and read through the checked reader again, so that damage done
// meanwhile still ends the stream in an error. A range is read as stored: the client
// checks the blob it assembles from ranges (blob.proto).
func (b *blobServer) DownloadBlob(req *pb.DownloadBlobRequest, stream pb.BlobService_DownloadBlobServer) error {
	if err := checkDigest(req.GetDigest()); err != nil {
		return err
	}
	if fe := rules.Check(req); fe != nil {
		return errs.Field(fe.Field, "%s", fe.Message)
	}
	ctx := stream.Context()
	r, info, err := b.open(ctx, req)
	if err != nil {
		return err
	}
	defer r.Close()
	buf := make([]byte, rules.RPC.GetMaxDownloadChunkBytes())
	first := true
	for {
		n, err := io.ReadFull(r, buf)
		if n > 0 || first {
			msg := &pb.DownloadBlobResponse{Chunk: buf[:n]}
			if first {
				msg.SizeBytes = info.Size
				first = false
			}
			if serr := stream.Send(msg); serr != nil {
				return serr
			}
		}
		if errors.Is(err, io.EOF) || errors.Is(err, io.ErrUnexpectedEOF) {
			return nil
		}
		if err != nil {
			return err // the store's kind: DataLoss for damage, Internal for a failed read
		}
	}
}

// open opens what a download asks for: the whole blob verified and checked as read, or a
// range as stored.
func (b *blobServer) open(ctx context.Context, req *pb.DownloadBlobRequest) (io.ReadCloser, blobstore.Info, error) {
	info, err := b.s.cfg.Blobs.Stat(ctx, req.GetDigest())
	if err != nil {
		return nil, blobstore.Info{}, err
	}
	if req.GetOffset() == 0 && (req.GetLength() == 0 || req.GetLength() >= info.Size) {
		if _, err := b.s.verifiedBlob(ctx, req.GetDigest()); err != nil {
			return nil, blobstore.Info{}, err
		}
		return b.s.cfg.Blobs.Open(ctx, req.GetDigest())
	}
	return b.s.cfg.Blobs.OpenRange(ctx, req.GetDigest(), req.GetOffset(), req.GetLength())
}

func (b *blobServer) GetBlobInfo(ctx context.Context, req *pb.GetBlobInfoRequest) (*pb.GetBlobInfoResponse, error) {
	if err := checkDigest(req.GetDigest()); err != nil {
		return nil, err
	}
	info, err := b.s.verifiedBlob(ctx, req.GetDigest())
	if err != nil {
		return nil, err
	}
	return &pb.GetBlobInfoResponse{Digest: info.Digest, SizeBytes: info.Size}, nil
}

// verifiedBlob checks a stored blob whole against its digest (blobstore.Store.Verify),
// logging damage, which an operator should hear of: a disk may be failing.
func (s *Service) verifiedBlob(ctx context.Context, digest string) (blobstore.Info, error) {
	info, err := s.cfg.Blobs.Verify(ctx, digest)
	if errs.Is(err, errs.DataLoss) {
		s.log.Error("damaged blob", "digest", digest, "err", err)
	}
	return info, err
}

// inHeader names the blob store's complaints about size and digest as the header fields
// of the upload request.
func inHeader(err error) error {
	var e *errs.Error
	if errors.As(err, &e) && (e.Field == "size_bytes" || e.Field == "digest") {
		c := *e
		c.Field = "header." + e.Field
		return &c
	}
	return err
}
