package assets_test

import (
	"bytes"
	"context"
	"encoding/binary"
	"errors"
	"image"
	"image/jpeg"
	"image/png"
	"io"
	"strings"
	"testing"

	"photonfarm/contract/assets"
	"photonfarm/contract/assets/assetstest"
)

func pngOf(t *testing.T, w, h int) []byte {
	t.Helper()
	var b bytes.Buffer
	if err := png.Encode(&b, image.NewRGBA(image.Rect(0, 0, w, h))); err != nil {
		t.Fatal(err)
	}
	return b.Bytes()
}

// exrOf is an OpenEXR header with one attribute before the data window.
func exrOf(xMin, yMin, xMax, yMax int32) []byte {
	var b bytes.Buffer
	b.Write([]byte{0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0})
	attr := func(name, typ string, value []byte) {
		b.WriteString(name + "\x00" + typ + "\x00")
		binary.Write(&b, binary.LittleEndian, uint32(len(value)))
		b.Write(value)
	}
	attr("compression", "compression", []byte{0})
	var box bytes.Buffer
	binary.Write(&box, binary.LittleEndian, [4]int32{xMin, yMin, xMax, yMax})
	attr("dataWindow", "box2i", box.Bytes())
	b.WriteByte(0)
	return b.Bytes()
}

func checkTexture(b []byte) (assets.Texture, error) {
	open := func() (io.ReadCloser, error) { return io.NopCloser(bytes.NewReader(b)), nil }
	return assets.CheckTexture(context.Background(), open, 1<<30, assets.MaxTexturePixels())
}

func TestCheckTextureReadsEachFormatsSize(t *testing.T) {
	var jpg bytes.Buffer
	if err := jpeg.Encode(&jpg, image.NewRGBA(image.Rect(0, 0, 5, 3)), nil); err != nil {
		t.Fatal(err)
	}
	for _, tt := range []struct {
		name string
		file []byte
		want assets.Texture
	}{
		{"png", pngOf(t, 7, 4), assets.Texture{Format: "png", Width: 7, Height: 4}},
		{"jpeg", jpg.Bytes(), assets.Texture{Format: "jpeg", Width: 5, Height: 3}},
		{"openexr", exrOf(-2, 0, 9, 4), assets.Texture{Format: "openexr", Width: 12, Height: 5}},
		{"hdr", []byte("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1\n\n-Y 6 +X 11\n\x02\x02"), assets.Texture{Format: "hdr", Width: 11, Height: 6}},
	} {
		got, err := checkTexture(tt.file)
		if err != nil || got != tt.want {
			t.Errorf("%s: CheckTexture = %+v, %v; want %+v", tt.name, got, err, tt.want)
		}
	}
}

func TestCheckTextureRefusals(t *testing.T) {
	for _, tt := range []struct {
		name, reason string
		file         []byte
	}{
		{"not an image", "not an image this farm reads", []byte("v 0 0 0\nf 1 2 3\n")},
		{"empty file", "not an image", nil},
		{"65536 x 65536 PNG", "a png image of 65536x65536 pixels is larger than", assetstest.PNGHeader(65536, 65536)},
		{"truncated PNG", "does not parse", pngOf(t, 4, 4)[:20]},
		{"EXR without a data window", "without a dataWindow", []byte{0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0, 0}},
		{"empty EXR data window", "is empty", exrOf(5, 0, 4, 3)},
		{"cut EXR header", "cut short", exrOf(0, 0, 3, 3)[:20]},
		{"HDR in XYZ", "in XYZ", []byte("#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 2 +X 2\n")},
		{"HDR with a rotated resolution", "does not read", []byte("#?RADIANCE\n\n+X 2 -Y 2\n")},
		{"a #? file that is not HDR", "not a Radiance HDR file", []byte("#?SOMETHING\n\n")},
	} {
		_, err := checkTexture(tt.file)
		var bad *assets.TextureError
		if !errors.As(err, &bad) || !strings.Contains(bad.Reason, tt.reason) {
			t.Errorf("%s: CheckTexture = %v, want a refusal containing %q", tt.name, err, tt.reason)
		}
		var refusal assets.Refusal
		if !errors.As(err, &refusal) {
			t.Errorf("%s: %v is not an assets.Refusal", tt.name, err)
		}
	}
}

func TestCheckTextureRefusesAFilePastTheSizeLimit(t *testing.T) {
	open := func() (io.ReadCloser, error) { return io.NopCloser(bytes.NewReader(pngOf(t, 64, 64))), nil }
	_, err := assets.CheckTexture(context.Background(), open, 10, assets.MaxTexturePixels())
	var bad *assets.TextureError
	if !errors.As(err, &bad) {
		t.Errorf("CheckTexture of a PNG larger than 10 bytes = %v, want a refusal", err)
	}
}
