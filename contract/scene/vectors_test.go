package scene_test

import (
	"errors"
	"fmt"
	"os"
	"path/filepath"
	"strconv"
	"strings"
	"testing"

	"google.golang.org/protobuf/encoding/protojson"
	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/reflect/protoreflect"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// vectorDir holds the shared scene vectors (tests/vectors/scenes/README.md), which the
// worker's checker runs too.
const vectorDir = "../../tests/vectors/scenes"

// TestSharedSceneVectors runs every vector as the README says every side must: parse,
// grow, Validate, then check that each mesh file it names is among its assets; an
// accepted vector must pass all of it, a refused one must fail naming exactly its field.
func TestSharedSceneVectors(t *testing.T) {
	paths, err := filepath.Glob(filepath.Join(vectorDir, "*.json"))
	if err != nil || len(paths) < 100 {
		t.Fatalf("found %d vectors in %s (%v), want the generated set", len(paths), vectorDir, err)
	}
	for _, p := range paths {
		t.Run(strings.TrimSuffix(filepath.Base(p), ".json"), func(t *testing.T) {
			vec := readVector(t, p)
			err := checkVector(vec)
			var fe *scene.FieldError
			switch {
			case vec.GetRefusedField() == "" && err != nil:
				t.Errorf("refused, want accepted: %v", err)
			case vec.GetRefusedField() != "" && err == nil:
				t.Errorf("accepted, want refused at %s", vec.GetRefusedField())
			case vec.GetRefusedField() != "" && (!errors.As(err, &fe) || fe.Field != vec.GetRefusedField()):
				t.Errorf("refused with %v, want the field %s", err, vec.GetRefusedField())
			}
		})
	}
}

func readVector(t *testing.T, path string) *pb.SceneVector {
	t.Helper()
	data, err := os.ReadFile(path)
	if err != nil {
		t.Fatal(err)
	}
	vec := &pb.SceneVector{}
	if err := protojson.Unmarshal(data, vec); err != nil {
		t.Fatalf("%s: %v", path, err)
	}
	for _, g := range vec.GetGrow() {
		if err := grow(vec.GetScene(), g); err != nil {
			t.Fatalf("%s: grow %s: %v", path, g.GetPath(), err)
		}
	}
	return vec
}

// checkVector validates the vector's scene, then checks that every mesh file it names is
// an asset of the vector whose bytes have that digest (as if uploaded).
func checkVector(vec *pb.SceneVector) error {
	s := vec.GetScene()
	if err := scene.Validate(s); err != nil {
		return err
	}
	for _, ref := range scene.Files(s) {
		if ref.Kind != scene.MeshFile {
			continue
		}
		file, ok := vec.GetAssets()[ref.Digest]
		if !ok {
			return &scene.FieldError{Field: ref.Field + ".digest", Message: "no such blob"}
		}
		data, err := os.ReadFile(filepath.Join(vectorDir, file))
		if err != nil {
			return err
		}
		if rules.DigestOf(data) != ref.Digest {
			return fmt.Errorf("asset %s does not have the digest %s", file, ref.Digest)
		}
	}
	return nil
}

// grow appends copies of the last element of the list at g's path in s until it has
// g.count elements (vectors.proto's GrowField).
func grow(s *pb.Scene, g *pb.GrowField) error {
	msg := s.ProtoReflect()
	parts := strings.Split(g.GetPath(), ".")
	for i, part := range parts {
		name, index, indexed := strings.Cut(part, "[")
		fd := msg.Descriptor().Fields().ByName(protoreflect.Name(name))
		if fd == nil || (indexed || i == len(parts)-1) && !fd.IsList() {
			return fmt.Errorf("%s is not a list field of %s", name, msg.Descriptor().FullName())
		}
		switch {
		case i == len(parts)-1 && indexed:
			return errors.New("names an element, not a list")
		case i == len(parts)-1:
			list := msg.Mutable(fd).List()
			if list.Len() == 0 {
				return errors.New("the list is empty")
			}
			last := list.Get(list.Len() - 1)
			for uint64(list.Len()) < g.GetCount() {
				if fd.Kind() == protoreflect.MessageKind {
					list.Append(protoreflect.ValueOfMessage(proto.Clone(last.Message().Interface()).ProtoReflect()))
				} else {
					list.Append(last)
				}
			}
		case indexed:
			n, err := strconv.Atoi(strings.TrimSuffix(index, "]"))
			list := msg.Mutable(fd).List()
			if err != nil || n < 0 || n >= list.Len() {
				return fmt.Errorf("no element %s of %s", index, name)
			}
			msg = list.Get(n).Message()
		default:
			msg = msg.Mutable(fd).Message()
		}
	}
	return nil
}
