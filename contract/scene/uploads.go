package scene

import (
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// A scene file names its mesh files and reference image by path; the client uploads each
// and sets its digest, keeping the path to name the file in messages. A submitted scene
// with a path but no digest is one the client has not finished: the error says so.
const notUploaded = "missing; clients upload the file named by path and set its digest"

// explainUpload returns err, a refusal of rules.Check, saying whose job the digest is when
// it refuses a missing mesh digest beside a path (shapes[i].mesh.digest).
func explainUpload(s *pb.Scene, err *FieldError) *FieldError {
	for i, sh := range s.GetShapes() {
		if m := sh.GetMesh(); m != nil && m.GetPath() != "" && m.GetDigest() == "" && err.Field == index("shapes", i)+".mesh.digest" {
			err.Message = notUploaded
		}
	}
	return err
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

// BlobRefs lists every blob s refers to by digest: its mesh files in shape order, then its
// reference image (Field "progressive.reference.digest"), if it names one.
func BlobRefs(s *pb.Scene) []MeshRef {
	refs := MeshRefs(s)
	if d := ReferenceDigest(s); d != "" {
		refs = append(refs, MeshRef{Field: "progressive.reference.digest", Digest: d})
	}
	return refs
}
