package assets

import (
	"bufio"
	"bytes"
	"context"
	"encoding/binary"
	"fmt"
	"image"
	_ "image/jpeg" // registers JPEG with image.DecodeConfig
	_ "image/png"  // registers PNG
	"io"
	"regexp"
	"strconv"

	"photonfarm/contract/rules"
)

// Texture is what checking an image file learnt of it: its format and size. Only the
// header is read: a 65,536 x 65,536 texture is refused without allocating its pixels.
type Texture struct {
	// Format is "png", "jpeg", "openexr" or "hdr" (Radiance RGBE).
	Format        string
	Width, Height uint64
}

// TextureError says what is wrong with an image file.
type TextureError struct{ Reason string }

func (e *TextureError) Error() string { return e.Reason }

func (*TextureError) refused() {}

// MaxTexturePixels is the contract's largest texture (width times height).
func MaxTexturePixels() uint64 { return rules.Scene.GetMaxTexturePixels() }

// CheckTexture reads the header of the image open opens (PNG, JPEG, OpenEXR or Radiance
// HDR, told apart by their magic numbers) and checks its size against maxPixels. It returns
// the image's format and size, a *TextureError saying what is wrong (not an image, a
// header that does not parse, a size of 0 or past the limit), the error of opening or
// reading the file, or ctx's error.
func CheckTexture(ctx context.Context, open Opener, maxBytes, maxPixels uint64) (Texture, error) {
	f, err := open()
	if err != nil {
		return Texture{}, err
	}
	defer f.Close()
	r := bufio.NewReader(&limitedReader{ctx: ctx, r: f, left: maxBytes})
	head, err := r.Peek(16)
	if err != nil && err != io.EOF && err != bufio.ErrBufferFull {
		if ctx.Err() != nil {
			return Texture{}, ctx.Err()
		}
		if err != errTooLarge {
			return Texture{}, err
		}
	}
	var t Texture
	switch {
	case bytes.HasPrefix(head, []byte("\x89PNG\r\n\x1a\n")), bytes.HasPrefix(head, []byte("\xff\xd8\xff")):
		cfg, format, err := image.DecodeConfig(r)
		if err != nil {
			return Texture{}, readFailure(ctx, err, "the image header does not parse: "+err.Error())
		}
		t = Texture{Format: format, Width: uint64(cfg.Width), Height: uint64(cfg.Height)}
	case bytes.HasPrefix(head, exrMagic):
		if t, err = exrHeader(r); err != nil {
			return Texture{}, readFailure(ctx, err, "")
		}
	case bytes.HasPrefix(head, []byte("#?")):
		if t, err = hdrHeader(r); err != nil {
			return Texture{}, readFailure(ctx, err, "")
		}
	default:
		return Texture{}, &TextureError{"not an image this farm reads (PNG, JPEG, OpenEXR or Radiance HDR)"}
	}
	switch {
	case t.Width == 0 || t.Height == 0:
		return Texture{}, &TextureError{fmt.Sprintf("a %s image of %dx%d pixels is empty", t.Format, t.Width, t.Height)}
	case t.Width > maxPixels || t.Height > maxPixels || t.Width*t.Height > maxPixels:
		return Texture{}, &TextureError{fmt.Sprintf("a %s image of %dx%d pixels is larger than the %d pixels a texture may have", t.Format, t.Width, t.Height, maxPixels)}
	}
	return t, nil
}

// readFailure is what a failure to read a header becomes: the reader's own refusal, ctx's
// error, or a refusal with reason (a header cut short, a file past the size limit).
func readFailure(ctx context.Context, err error, reason string) error {
	if _, ok := err.(*TextureError); ok {
		return err
	}
	if ctx.Err() != nil {
		return ctx.Err()
	}
	if err == errTooLarge {
		return &TextureError{"the file is larger than the limit of one asset"}
	}
	if reason == "" {
		reason = "the image header is cut short or unreadable: " + err.Error()
	}
	return &TextureError{reason}
}

var exrMagic = []byte{0x76, 0x2f, 0x31, 0x01}

// exrHeader reads an OpenEXR file's first header (single or multi-part) up to its
// dataWindow attribute: a box2i of xMin, yMin, xMax, yMax.
func exrHeader(r *bufio.Reader) (Texture, error) {
	var pre [8]byte // magic and version
	if _, err := io.ReadFull(r, pre[:]); err != nil {
		return Texture{}, err
	}
	for attrs := 0; ; attrs++ {
		if attrs > 1024 {
			return Texture{}, &TextureError{"an OpenEXR header of more than 1024 attributes"}
		}
		name, err := exrString(r)
		if err != nil {
			return Texture{}, err
		}
		if name == "" {
			return Texture{}, &TextureError{"an OpenEXR header without a dataWindow attribute"}
		}
		typ, err := exrString(r)
		if err != nil {
			return Texture{}, err
		}
		var size uint32
		if err := binary.Read(r, binary.LittleEndian, &size); err != nil {
			return Texture{}, err
		}
		if name == "dataWindow" {
			if typ != "box2i" || size != 16 {
				return Texture{}, &TextureError{fmt.Sprintf("an OpenEXR dataWindow of type %q and %d bytes, not a box2i", typ, size)}
			}
			var box [4]int32
			if err := binary.Read(r, binary.LittleEndian, &box); err != nil {
				return Texture{}, err
			}
			if box[2] < box[0] || box[3] < box[1] {
				return Texture{}, &TextureError{fmt.Sprintf("an OpenEXR dataWindow (%d, %d)-(%d, %d) that is empty", box[0], box[1], box[2], box[3])}
			}
			return Texture{Format: "openexr", Width: uint64(int64(box[2]) - int64(box[0]) + 1), Height: uint64(int64(box[3]) - int64(box[1]) + 1)}, nil
		}
		if _, err := r.Discard(int(size)); err != nil {
			return Texture{}, err
		}
	}
}

// exrString reads a NUL-terminated attribute name or type (at most 255 bytes).
func exrString(r *bufio.Reader) (string, error) {
	var b []byte
	for {
		c, err := r.ReadByte()
		if err != nil {
			return "", err
		}
		if c == 0 {
			return string(b), nil
		}
		if len(b) == 255 {
			return "", &TextureError{"an OpenEXR attribute name longer than 255 bytes"}
		}
		b = append(b, c)
	}
}

// hdrResolution is a Radiance HDR file's resolution line in the usual orientation.
var hdrResolution = regexp.MustCompile(`^[-+]Y ([0-9]{1,9}) [-+]X ([0-9]{1,9})$`)

// hdrHeader reads a Radiance HDR header: "#?RADIANCE" (or "#?RGBE"), lines up to a blank
// one, then the resolution line "-Y height +X width".
func hdrHeader(r *bufio.Reader) (Texture, error) {
	line := func() (string, error) {
		b, err := r.ReadSlice('\n')
		if err == bufio.ErrBufferFull {
			return "", &TextureError{"a Radiance HDR header line longer than 4096 bytes"}
		}
		if err != nil {
			return "", err
		}
		return string(bytes.TrimRight(b, "\r\n")), nil
	}
	first, err := line()
	if err != nil {
		return Texture{}, err
	}
	if first != "#?RADIANCE" && first != "#?RGBE" {
		return Texture{}, &TextureError{fmt.Sprintf("not a Radiance HDR file (first line %q)", rules.Truncate(first, 40))}
	}
	for n := 0; ; n++ {
		l, err := line()
		if err != nil {
			return Texture{}, err
		}
		if l == "" {
			break
		}
		if n > 256 {
			return Texture{}, &TextureError{"a Radiance HDR header of more than 256 lines"}
		}
		if l == "FORMAT=32-bit_rle_xyze" {
			return Texture{}, &TextureError{"a Radiance HDR file in XYZ, not RGB"}
		}
	}
	res, err := line()
	if err != nil {
		return Texture{}, err
	}
	m := hdrResolution.FindStringSubmatch(res)
	if m == nil {
		return Texture{}, &TextureError{fmt.Sprintf("a Radiance HDR resolution line %q this farm does not read (it reads \"-Y H +X W\")", rules.Truncate(res, 40))}
	}
	h, _ := strconv.ParseUint(m[1], 10, 64)
	w, _ := strconv.ParseUint(m[2], 10, 64)
	return Texture{Format: "hdr", Width: w, Height: h}, nil
}
