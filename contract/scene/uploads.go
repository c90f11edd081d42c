package scene

import (
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// A scene file names its mesh files and reference image by path; the client uploads each
// and sets its digest, keeping the path to name the file in messages. A submitted scene
// with a path but no digest is one the client has not finished: the error says so.
const notUploaded = "missing; clients upload the file named by path and set its digest"

// meshNotUploaded: a mesh with a path has its digest (shapes[i].mesh.digest).
func meshNotUploaded(s *pb.Scene) *FieldError {
	for i, sh := range s.GetShapes() {
		if m := sh.GetMesh(); m != nil && m.GetPath() != "" && m.GetDigest() == "" {
			return rules.Errorf(index("shapes", i)+".mesh.digest", notUploaded)
		}
	}
	return nil
}

// checkReference: a reference image with a path has its digest
// (progressive.reference.digest).
func checkReference(s *pb.Scene) *FieldError {
	if r := s.GetProgressive().GetReference(); r.GetPath() != "" && r.GetDigest() == "" {
		return rules.Errorf("progressive.reference.digest", notUploaded)
	}
	return nil
}

// MeshRef is a mesh file a scene refers to by digest.
type MeshRef struct {
	// Field is the digest's path, "shapes[3].mesh.digest".
	Field  string
	Digest string
}

// MeshRefs lists the mesh files s refers to, in shape order.
func MeshRefs(s *pb.Scene) []MeshRef {
	var refs []MeshRef
	for i, sh := range s.GetShapes() {
		if m := sh.GetMesh(); m != nil {
			refs = append(refs, MeshRef{Field: index("shapes", i) + ".mesh.digest", Digest: m.GetDigest()})
		}
	}
	return refs
}
