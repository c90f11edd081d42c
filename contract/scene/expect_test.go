package scene_test

import (
	"errors"
	"strings"
	"testing"

	"photonfarm/contract/scene"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// variant is a change to scenetest.Valid(64, 48).
type variant struct {
	name   string
	mutate func(*pb.Scene)
}

// refusal is a variant Validate must refuse, naming field, with message in its text.
type refusal struct {
	name    string
	mutate  func(*pb.Scene)
	field   string
	message string // substring
}

// validate validates scenetest.Valid(64, 48) changed by mutate.
func validate(mutate func(*pb.Scene)) error {
	s := scenetest.Valid(64, 48)
	mutate(s)
	return scene.Validate(s)
}

// validated returns scenetest.Valid(8, 8) changed by mutate, which Validate must accept.
func validated(t *testing.T, mutate func(*pb.Scene)) *pb.Scene {
	t.Helper()
	s := scenetest.Valid(8, 8)
	mutate(s)
	if err := scene.Validate(s); err != nil {
		t.Fatal(err)
	}
	return s
}

// expectValid checks that Validate accepts every variant.
func expectValid(t *testing.T, tests []variant) {
	t.Helper()
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			if err := validate(tt.mutate); err != nil {
				t.Fatalf("Validate: %v", err)
			}
		})
	}
}

// expectRefused checks that Validate refuses every variant with a *FieldError naming the
// field, whose text starts with the field.
func expectRefused(t *testing.T, tests []refusal) {
	t.Helper()
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			err := validate(tt.mutate)
			var fe *scene.FieldError
			if !errors.As(err, &fe) {
				t.Fatalf("Validate = %v, want a *FieldError", err)
			}
			if fe.Field != tt.field || !strings.Contains(fe.Message, tt.message) {
				t.Errorf("Validate = %q; want field %q and a message containing %q", err, tt.field, tt.message)
			}
			if !strings.HasPrefix(err.Error(), tt.field+": ") {
				t.Errorf("Error() = %q, want it to start with the field", err)
			}
		})
	}
}
