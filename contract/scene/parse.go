// Package scene parses and validates scenes (renderfarm.v1.Scene) and applies defaults.
package scene

import (
	"errors"
	"regexp"
	"strconv"
	"strings"

	"google.golang.org/protobuf/encoding/protojson"

	pb "photonfarm/proto/renderfarm/v1"
)

// protojson prefixes its errors with "proto:" followed by a space that is sometimes a
// non-breaking one (on purpose, to discourage parsing); we only strip that prefix and
// turn "(line 3:5): " into "line 3:5: ".
var (
	protoPrefix = regexp.MustCompile(`^proto:[\s\x{00a0}]*`)
	linePos     = regexp.MustCompile(`^(?:syntax error )?\((line \d+:\d+)\):[\s\x{00a0}]*`)
)

// ParseJSON decodes a scene from protobuf's canonical JSON mapping. Malformed JSON is
// reported with its line and column. An unknown field or enum value is an error naming
// its line, its field path and the declared name nearest to it (`scene: line 3:20:
// shapes[0].sphere.radus: unknown field "radus" (did you mean "radius"?)`). ParseJSON
// does not validate; call Validate.
func ParseJSON(data []byte) (*pb.Scene, error) {
	s := &pb.Scene{}
	if err := (protojson.UnmarshalOptions{DiscardUnknown: false}).Unmarshal(data, s); err != nil {
		msg := protoPrefix.ReplaceAllString(err.Error(), "")
		msg = linePos.ReplaceAllString(msg, "$1: ")
		// The walk explains protojson's error only if both are about the same name: an
		// earlier error of another kind (a string for a number) is protojson's to say.
		if m := findMisspelling(data, s.ProtoReflect().Descriptor()); m != nil && strings.Contains(msg, strconv.Quote(m.name)) {
			line, _, _ := strings.Cut(msg, ": ")
			if !strings.HasPrefix(line, "line ") {
				line = ""
			} else {
				line += ": "
			}
			msg = line + m.String()
		}
		return nil, errors.New("scene: " + msg)
	}
	return s, nil
}
