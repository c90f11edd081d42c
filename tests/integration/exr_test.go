package integration

import (
	"bytes"
	"encoding/binary"
	"errors"
	"fmt"
	"image/color"
	"image/png"
	"math"
	"slices"
	"strings"
	"testing"

	"photonfarm/tests/farmtest"
)

// exrHeader is what the tests check of an OpenEXR file: the attributes of its (first)
// header, read by hand from the bytes so that no image library is needed.
type exrHeader struct {
	Tiled, MultiPart bool
	DataWindow       [4]int32 // xMin, yMin, xMax, yMax
	DisplayWindow    [4]int32
	Channels         []exrChannel      // in file order (sorted by name)
	TileW, TileH     uint32            // from the "tiles" attribute
	TileMode         byte              // level mode in the low nibble: 0 ONE_LEVEL
	Compression      byte              // 3 ZIP
	Attributes       map[string]string // name -> type
	Values           map[string][]byte // name -> the value's bytes
}

type exrChannel struct {
	Name      string
	PixelType int32 // 0 UINT, 1 HALF, 2 FLOAT
	XSampling int32
	YSampling int32
}

const (
	exrMagic        = 20000630
	exrFlagTiled    = 0x200
	exrFlagNonImage = 0x800
	exrFlagMulti    = 0x1000
	exrPixelFloat   = 2
)

// parseEXRHeader reads the magic number, version field and first header of an OpenEXR
// file (https://openexr.com/en/latest/OpenEXRFileLayout.html).
func parseEXRHeader(b []byte) (*exrHeader, error) {
	if len(b) < 8 || binary.LittleEndian.Uint32(b) != exrMagic {
		return nil, errors.New("not an OpenEXR file (bad magic number)")
	}
	version := binary.LittleEndian.Uint32(b[4:])
	if version&0xff != 2 {
		return nil, fmt.Errorf("OpenEXR version %d, want 2", version&0xff)
	}
	if version&exrFlagNonImage != 0 {
		return nil, errors.New("deep (non-image) OpenEXR")
	}
	h := &exrHeader{
		Tiled:      version&exrFlagTiled != 0,
		MultiPart:  version&exrFlagMulti != 0,
		Attributes: map[string]string{},
		Values:     map[string][]byte{},
	}
	r := b[8:]
	cstr := func() (string, error) {
		i := bytes.IndexByte(r, 0)
		if i < 0 {
			return "", errors.New("truncated header")
		}
		s := string(r[:i])
		r = r[i+1:]
		return s, nil
	}
	for {
		name, err := cstr()
		if err != nil {
			return nil, err
		}
		if name == "" {
			break // end of header
		}
		typ, err := cstr()
		if err != nil {
			return nil, err
		}
		if len(r) < 4 {
			return nil, errors.New("truncated header")
		}
		size := int(binary.LittleEndian.Uint32(r))
		r = r[4:]
		if size < 0 || size > len(r) {
			return nil, fmt.Errorf("attribute %s: size %d past the end", name, size)
		}
		v := r[:size]
		r = r[size:]
		h.Attributes[name] = typ
		h.Values[name] = v
		switch {
		case name == "channels" && typ == "chlist":
			for len(v) > 0 && v[0] != 0 {
				i := bytes.IndexByte(v, 0)
				if i < 0 || len(v) < i+1+16 {
					return nil, errors.New("channels: truncated")
				}
				c := exrChannel{Name: string(v[:i])}
				v = v[i+1:]
				c.PixelType = int32(binary.LittleEndian.Uint32(v))
				c.XSampling = int32(binary.LittleEndian.Uint32(v[8:]))
				c.YSampling = int32(binary.LittleEndian.Uint32(v[12:]))
				v = v[16:]
				h.Channels = append(h.Channels, c)
			}
		case (name == "dataWindow" || name == "displayWindow") && typ == "box2i" && size == 16:
			var box [4]int32
			for i := range box {
				box[i] = int32(binary.LittleEndian.Uint32(v[4*i:]))
			}
			if name == "dataWindow" {
				h.DataWindow = box
			} else {
				h.DisplayWindow = box
			}
		case name == "tiles" && typ == "tiledesc" && size == 9:
			h.TileW = binary.LittleEndian.Uint32(v)
			h.TileH = binary.LittleEndian.Uint32(v[4:])
			h.TileMode = v[8]
		case name == "compression" && typ == "compression" && size == 1:
			h.Compression = v[0]
		}
	}
	return h, nil
}

// aovChannels are the channels of a final image beyond the beauty R, G, B, A: the layers
// direct, indirect, caustic, volume, albedo, normal and depth (worker/render RenderChannels).
var aovChannels = []string{
	"direct.R", "direct.G", "direct.B",
	"indirect.R", "indirect.G", "indirect.B",
	"caustic.R", "caustic.G", "caustic.B",
	"volume.R", "volume.G", "volume.B",
	"albedo.R", "albedo.G", "albedo.B",
	"normal.X", "normal.Y", "normal.Z",
	"depth.Z",
}

// checkFinalEXR says what is wrong, if anything, with b as the final image of a width x
// height render with square tiles of side tile: a single-part tiled OpenEXR with FLOAT
// channels R, G, B, A and every one of extra (and possibly more), data window = display
// window = the image.
func checkFinalEXR(b []byte, width, height, tile int, extra ...string) error {
	h, err := parseEXRHeader(b)
	if err != nil {
		return err
	}
	var problems []string
	if !h.Tiled && !h.MultiPart {
		problems = append(problems, "not tiled")
	}
	want := [4]int32{0, 0, int32(width - 1), int32(height - 1)}
	if h.DataWindow != want {
		problems = append(problems, fmt.Sprintf("dataWindow %v, want %v", h.DataWindow, want))
	}
	if h.DisplayWindow != want {
		problems = append(problems, fmt.Sprintf("displayWindow %v, want %v", h.DisplayWindow, want))
	}
	if h.TileW != uint32(tile) || h.TileH != uint32(tile) || h.TileMode&0xf != 0 {
		problems = append(problems, fmt.Sprintf("tiles %dx%d mode %d, want %dx%d ONE_LEVEL", h.TileW, h.TileH, h.TileMode, tile, tile))
	}
	var names []string
	for _, c := range h.Channels {
		names = append(names, c.Name)
		if c.PixelType != exrPixelFloat || c.XSampling != 1 || c.YSampling != 1 {
			problems = append(problems, fmt.Sprintf("channel %s: type %d sampling %dx%d, want FLOAT 1x1", c.Name, c.PixelType, c.XSampling, c.YSampling))
		}
	}
	for _, n := range append([]string{"R", "G", "B", "A"}, extra...) {
		if !slices.Contains(names, n) {
			problems = append(problems, fmt.Sprintf("no %s channel (channels %v)", n, names))
		}
	}
	if len(problems) > 0 {
		return fmt.Errorf("final EXR: %v", problems)
	}
	return nil
}

// checkEXRMetadata says what is wrong, if anything, with the metadata of b as the final
// image of a render of samples per pixel over rounds (worker/image/exr_metadata.h): the
// standard chromaticities, worldToCamera and worldToNDC, a positive renderTime, the
// samples and rounds, and the worker that wrote it.
func checkEXRMetadata(b []byte, samples, rounds int) error {
	h, err := parseEXRHeader(b)
	if err != nil {
		return err
	}
	var problems []string
	want := func(name, typ string, size int) []byte {
		v := h.Values[name]
		if h.Attributes[name] != typ || (size > 0 && len(v) != size) {
			problems = append(problems, fmt.Sprintf("%s: type %q, %d bytes; want %s", name, h.Attributes[name], len(v), typ))
			return nil
		}
		return v
	}
	want("chromaticities", "chromaticities", 32)
	for _, m := range []string{"worldToCamera", "worldToNDC"} {
		if v := want(m, "m44f", 64); v != nil && math.Float32frombits(binary.LittleEndian.Uint32(v[60:])) == 0 {
			problems = append(problems, m+": its last element is 0 (not a camera or projection matrix)")
		}
	}
	if v := want("renderTime", "double", 8); v != nil && !(math.Float64frombits(binary.LittleEndian.Uint64(v)) > 0) {
		problems = append(problems, fmt.Sprintf("renderTime %v, want the seconds the job took", math.Float64frombits(binary.LittleEndian.Uint64(v))))
	}
	for name, n := range map[string]int{"samplesPerPixel": samples * rounds, "rounds": rounds} {
		if v := want(name, "int", 4); v != nil && int32(binary.LittleEndian.Uint32(v)) != int32(n) {
			problems = append(problems, fmt.Sprintf("%s %d, want %d", name, int32(binary.LittleEndian.Uint32(v)), n))
		}
	}
	if v := want("software", "string", 0); v != nil && !strings.HasPrefix(string(v), "photonfarm farm-worker ") {
		problems = append(problems, fmt.Sprintf("software %q, want photonfarm farm-worker and its version", v))
	}
	if len(problems) > 0 {
		return fmt.Errorf("final EXR metadata: %v", problems)
	}
	return nil
}

// pngSize returns the width and height in a PNG's IHDR chunk.
func pngSize(b []byte) (int, int, error) {
	if len(b) < 24 || !bytes.Equal(b[:8], []byte("\x89PNG\r\n\x1a\n")) || string(b[12:16]) != "IHDR" {
		return 0, 0, errors.New("not a PNG file")
	}
	return int(binary.BigEndian.Uint32(b[16:])), int(binary.BigEndian.Uint32(b[20:])), nil
}

// pngLitAndCovered counts the pixels of a PNG whose colour is not black and those whose
// alpha is not 0.
func pngLitAndCovered(b []byte) (lit, covered int, err error) {
	img, err := png.Decode(bytes.NewReader(b))
	if err != nil {
		return 0, 0, err
	}
	for y := img.Bounds().Min.Y; y < img.Bounds().Max.Y; y++ {
		for x := img.Bounds().Min.X; x < img.Bounds().Max.X; x++ {
			c := color.NRGBAModel.Convert(img.At(x, y)).(color.NRGBA)
			if c.R|c.G|c.B != 0 {
				lit++
			}
			if c.A != 0 {
				covered++
			}
		}
	}
	return lit, covered, nil
}

// exrAttr appends one header attribute to b, for building test headers.
func exrAttr(b []byte, name, typ string, value []byte) []byte {
	b = append(b, name...)
	b = append(b, 0)
	b = append(b, typ...)
	b = append(b, 0)
	b = binary.LittleEndian.AppendUint32(b, uint32(len(value)))
	return append(b, value...)
}

func testEXR(tiled bool, pixelType int32, w, h, tile int, extra ...string) []byte {
	b := binary.LittleEndian.AppendUint32(nil, exrMagic)
	version := uint32(2)
	if tiled {
		version |= exrFlagTiled
	}
	b = binary.LittleEndian.AppendUint32(b, version)
	var ch []byte
	names := append([]string{"A", "B", "G", "R"}, extra...)
	slices.Sort(names) // OpenEXR stores channels sorted by name
	for _, n := range names {
		ch = append(ch, n...)
		ch = append(ch, 0)
		ch = binary.LittleEndian.AppendUint32(ch, uint32(pixelType))
		ch = append(ch, 0, 0, 0, 0)
		ch = binary.LittleEndian.AppendUint32(ch, 1)
		ch = binary.LittleEndian.AppendUint32(ch, 1)
	}
	ch = append(ch, 0)
	b = exrAttr(b, "channels", "chlist", ch)
	b = exrAttr(b, "compression", "compression", []byte{3})
	var box []byte
	for _, v := range []int32{0, 0, int32(w - 1), int32(h - 1)} {
		box = binary.LittleEndian.AppendUint32(box, uint32(v))
	}
	b = exrAttr(b, "dataWindow", "box2i", box)
	b = exrAttr(b, "displayWindow", "box2i", box)
	if tiled {
		td := binary.LittleEndian.AppendUint32(nil, uint32(tile))
		td = binary.LittleEndian.AppendUint32(td, uint32(tile))
		b = exrAttr(b, "tiles", "tiledesc", append(td, 0))
	}
	return append(b, 0)
}

func TestEXRHeaderCheckAcceptsTiledFloatRGBA(t *testing.T) {
	if err := checkFinalEXR(testEXR(true, exrPixelFloat, 64, 48, 16), 64, 48, 16); err != nil {
		t.Fatal(err)
	}
}

func TestEXRHeaderCheckFindsAOVChannelsByName(t *testing.T) {
	b := testEXR(true, exrPixelFloat, 64, 48, 16, aovChannels...)
	if err := checkFinalEXR(b, 64, 48, 16, aovChannels...); err != nil {
		t.Fatal(err)
	}
	h, _ := parseEXRHeader(b)
	if len(h.Channels) != 4+len(aovChannels) || h.Channels[0].Name != "A" || h.Channels[len(h.Channels)-1].Name != slices.Max(aovChannels) {
		t.Errorf("channels = %v", h.Channels)
	}
	missing := testEXR(true, exrPixelFloat, 64, 48, 16, slices.DeleteFunc(slices.Clone(aovChannels), func(n string) bool { return n == "caustic.G" })...)
	if err := checkFinalEXR(missing, 64, 48, 16, aovChannels...); err == nil || !strings.Contains(err.Error(), "no caustic.G channel") {
		t.Errorf("a file without caustic.G: %v", err)
	}
}

func TestEXRHeaderCheckRefusesWhatIsWrong(t *testing.T) {
	for name, b := range map[string][]byte{
		"scanline":   testEXR(false, exrPixelFloat, 64, 48, 16),
		"half":       testEXR(true, 1, 64, 48, 16),
		"wrong size": testEXR(true, exrPixelFloat, 64, 47, 16),
		"wrong tile": testEXR(true, exrPixelFloat, 64, 48, 32),
		"png":        []byte("\x89PNG\r\n\x1a\n0000IHDR00000000"),
		"truncated":  testEXR(true, exrPixelFloat, 64, 48, 16)[:60],
	} {
		if err := checkFinalEXR(b, 64, 48, 16); err == nil {
			t.Errorf("%s: accepted", name)
		}
	}
}

func TestWithoutRenderTimeZeroesOnlyTheRenderTime(t *testing.T) {
	header := func(seconds float64) []byte {
		b := testEXR(true, exrPixelFloat, 64, 48, 16)
		b = b[:len(b)-1] // reopen the header
		b = exrAttr(b, "renderTime", "double", binary.LittleEndian.AppendUint64(nil, math.Float64bits(seconds)))
		b = exrAttr(b, "rounds", "int", binary.LittleEndian.AppendUint32(nil, 2))
		return append(b, 0, 42) // the end of the header and a byte of "pixels"
	}
	a, b := header(1.5), header(97.25)
	if bytes.Equal(a, b) {
		t.Fatal("the two headers are the same: the test would prove nothing")
	}
	za, zb := farmtest.WithoutRenderTime(a), farmtest.WithoutRenderTime(b)
	if !bytes.Equal(za, zb) || len(za) != len(a) {
		t.Errorf("renders that differ only in renderTime still differ: %q, %q", za, zb)
	}
	if h, err := parseEXRHeader(za); err != nil || !bytes.Equal(h.Values["renderTime"], make([]byte, 8)) || h.Values["rounds"][0] != 2 {
		t.Errorf("zeroed header: %v, %v", h, err)
	}
	if bytes.Equal(farmtest.WithoutRenderTime(header(1.5)), farmtest.WithoutRenderTime(append(header(1.5)[:len(a)-1], 43))) {
		t.Error("files that differ after the header compare equal")
	}
	if plain := testEXR(true, exrPixelFloat, 64, 48, 16); !bytes.Equal(farmtest.WithoutRenderTime(plain), plain) {
		t.Error("a file without renderTime changed")
	}
}
