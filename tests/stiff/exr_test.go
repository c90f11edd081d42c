package stiff

// Reading the final EXR's pixels with oiiotool (Debian's openimageio-tools, installed by
// scripts/install-deps.sh), parsing its text output:
//
//   - `oiiotool --info -v --stats FILE` gives the size, the channel list and, per channel,
//     the NaN and infinity counts as OpenImageIO sees them;
//   - `oiiotool --dumpdata FILE` prints every pixel as "Pixel (x, y): v0 v1 ..." in that
//     channel order, with nine decimals (enough for the radiances of these scenes, which
//     are kept between about 1e-3 and 1e5).
//
// Both are cross-checked: the counts of NaN and infinity from the stats must equal those
// in the dumped values, the dump must hold exactly width x height pixels of as many values
// as there are channels, and anything unparsable is an error, never a silent zero.

import (
	"bytes"
	"fmt"
	"math"
	"os/exec"
	"regexp"
	"strconv"
	"strings"
)

type image struct {
	width, height int
	channels      []string
	pix           []float64 // width*height*len(channels), pixel-major
	nanCount      []int     // per channel, from oiiotool --stats
	infCount      []int
}

func (im *image) channel(name string) int {
	for i, c := range im.channels {
		if c == name {
			return i
		}
	}
	return -1
}

func (im *image) at(x, y, c int) float64 {
	return im.pix[(y*im.width+x)*len(im.channels)+c]
}

var (
	sizeLine  = regexp.MustCompile(`:\s+(\d+)\s+x\s+(\d+),\s+(\d+) channel`)
	pixelLine = regexp.MustCompile(`^\s*Pixel \((\d+), (\d+)\):\s*(.*)$`)
)

func oiiotool(args ...string) (string, error) {
	cmd := exec.Command("oiiotool", args...)
	var out, errb bytes.Buffer
	cmd.Stdout, cmd.Stderr = &out, &errb
	if err := cmd.Run(); err != nil {
		return "", fmt.Errorf("oiiotool %s: %v: %s%s (oiiotool comes from Debian's openimageio-tools; scripts/install-deps.sh installs it)",
			strings.Join(args, " "), err, errb.String(), out.String())
	}
	return out.String(), nil
}

// readEXR reads every channel of the first subimage of the EXR at path.
func readEXR(path string) (*image, error) {
	info, err := oiiotool("--info", "-v", "--stats", path)
	if err != nil {
		return nil, err
	}
	im := &image{}
	m := sizeLine.FindStringSubmatch(info)
	if m == nil {
		return nil, fmt.Errorf("%s: no size in oiiotool --info output:\n%s", path, info)
	}
	im.width, _ = strconv.Atoi(m[1])
	im.height, _ = strconv.Atoi(m[2])
	nch, _ := strconv.Atoi(m[3])
	for _, line := range strings.Split(info, "\n") {
		line = strings.TrimSpace(line)
		if rest, ok := strings.CutPrefix(line, "channel list:"); ok {
			for _, c := range strings.Split(rest, ",") {
				im.channels = append(im.channels, strings.TrimSpace(c))
			}
		}
		if rest, ok := strings.CutPrefix(line, "Stats NanCount:"); ok {
			if im.nanCount, err = ints(rest); err != nil {
				return nil, fmt.Errorf("%s: NanCount: %v", path, err)
			}
		}
		if rest, ok := strings.CutPrefix(line, "Stats InfCount:"); ok {
			if im.infCount, err = ints(rest); err != nil {
				return nil, fmt.Errorf("%s: InfCount: %v", path, err)
			}
		}
	}
	if len(im.channels) != nch || len(im.nanCount) != nch || len(im.infCount) != nch {
		return nil, fmt.Errorf("%s: oiiotool reports %d channels but lists %d names, %d NaN counts and %d Inf counts:\n%s",
			path, nch, len(im.channels), len(im.nanCount), len(im.infCount), info)
	}

	dump, err := oiiotool("--dumpdata", path)
	if err != nil {
		return nil, err
	}
	im.pix = make([]float64, im.width*im.height*nch)
	seen := make([]bool, im.width*im.height)
	pixels := 0
	for _, line := range strings.Split(dump, "\n") {
		m := pixelLine.FindStringSubmatch(line)
		if m == nil {
			continue
		}
		x, _ := strconv.Atoi(m[1])
		y, _ := strconv.Atoi(m[2])
		if x >= im.width || y >= im.height || seen[y*im.width+x] {
			return nil, fmt.Errorf("%s: unexpected pixel line %q", path, line)
		}
		fields := strings.Fields(m[3])
		if len(fields) != nch {
			return nil, fmt.Errorf("%s: pixel (%d, %d) has %d values, want %d", path, x, y, len(fields), nch)
		}
		for c, s := range fields {
			v, err := strconv.ParseFloat(s, 64) // accepts nan, inf, -inf
			if err != nil {
				return nil, fmt.Errorf("%s: pixel (%d, %d) channel %s: %q: %v", path, x, y, im.channels[c], s, err)
			}
			im.pix[(y*im.width+x)*nch+c] = v
		}
		seen[y*im.width+x] = true
		pixels++
	}
	if pixels != im.width*im.height {
		return nil, fmt.Errorf("%s: oiiotool --dumpdata printed %d pixels, want %d", path, pixels, im.width*im.height)
	}
	for c := range im.channels {
		nan, inf := 0, 0
		for p := 0; p < pixels; p++ {
			v := im.pix[p*nch+c]
			if math.IsNaN(v) {
				nan++
			} else if math.IsInf(v, 0) {
				inf++
			}
		}
		if nan != im.nanCount[c] || inf != im.infCount[c] {
			return nil, fmt.Errorf("%s: channel %s: the dump holds %d NaN and %d Inf, the stats say %d and %d",
				path, im.channels[c], nan, inf, im.nanCount[c], im.infCount[c])
		}
	}
	return im, nil
}

func ints(s string) ([]int, error) {
	var out []int
	for _, f := range strings.Fields(s) {
		v, err := strconv.Atoi(f)
		if err != nil {
			return nil, err
		}
		out = append(out, v)
	}
	return out, nil
}
