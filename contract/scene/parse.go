// Package scene parses and validates scenes (renderfarm.v1.Scene) and applies defaults.
package scene

import (
	"errors"
	"regexp"

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

// ParseJSON decodes a scene from protobuf's canonical JSON mapping. Unknown fields are
// errors, named in the message (`scene: unknown field "radus"`); malformed JSON is
// reported with its line and column. ParseJSON does not validate; call Validate.
func ParseJSON(data []byte) (*pb.Scene, error) {
	s := &pb.Scene{}
	if err := (protojson.UnmarshalOptions{DiscardUnknown: false}).Unmarshal(data, s); err != nil {
		msg := protoPrefix.ReplaceAllString(err.Error(), "")
		msg = linePos.ReplaceAllString(msg, "$1: ")
		return nil, errors.New("scene: " + msg)
	}
	return s, nil
}
