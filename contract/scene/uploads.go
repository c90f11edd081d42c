package scene

import (
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// A scene file names its mesh files, grid files and reference image by path; the client uploads each
// and sets its digest, keeping the path to name the file in messages. A submitted scene
// with a path but no digest is one the client has not finished: the error says so.
const notUploaded = "missing; clients upload the file named by path and set its digest"

// explainUpload returns err, a refusal of rules.Check, saying whose job the digest is when
// it refuses a missing digest beside a path (shapes[i].mesh.digest, medium.grid.digest).
func explainUpload(s *pb.Scene, err *FieldError) *FieldError {
	for _, f := range Files(s) {
		if f.Path != "" && f.Digest == "" && err.Field == f.Field+".digest" {
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
