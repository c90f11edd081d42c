package scene

import (
	pb "photonfarm/proto/renderfarm/v1"
)

// FileKind is what a file a scene names holds, which decides how it is checked.
type FileKind int

const (
	// MeshFile: an OBJ or farm mesh file (a shape's mesh, a mesh part).
	MeshFile FileKind = iota + 1
	// TextureFile: an image (PNG, JPEG, OpenEXR, Radiance HDR).
	TextureFile
	// ReferenceFile: the OpenEXR image the error is measured against.
	ReferenceFile
	// GridFile: a farm grid file, a heterogeneous medium's densities
	// (docs/grid-format.md).
	GridFile
)

// File is one file a scene names by path and digest: in a scene file by path (which the
// client resolves, checks, uploads and digests), in a submitted scene by digest.
type File struct {
	// Field names the message that holds the file: "shapes[3].mesh",
	// "meshes[0].parts[1]", "textures[2]", "progressive.reference", "medium.grid",
	// "shapes[4].interior_medium.grid".
	Field  string
	Kind   FileKind
	Path   string
	Digest string
	// SetDigest sets the digest in the scene.
	SetDigest func(digest string)
}

// Files lists every file s names, in field order: shapes' mesh files and their interior
// media's grids, the reference image, mesh parts, textures, the scene medium's grid.
func Files(s *pb.Scene) []File {
	var files []File
	for i, sh := range s.GetShapes() {
		if m := sh.GetMesh(); m != nil {
			files = append(files, File{Field: index("shapes", i) + ".mesh", Kind: MeshFile, Path: m.GetPath(), Digest: m.GetDigest(),
				SetDigest: func(d string) { m.Digest = d }})
		}
		files = appendGrid(files, index("shapes", i)+".interior_medium.grid", sh.GetInteriorMedium())
	}
	if r := s.GetProgressive().GetReference(); r != nil && (r.GetPath() != "" || r.GetDigest() != "") {
		files = append(files, File{Field: "progressive.reference", Kind: ReferenceFile, Path: r.GetPath(), Digest: r.GetDigest(),
			SetDigest: func(d string) { r.Digest = d }})
	}
	for i, m := range s.GetMeshes() {
		for j, p := range m.GetParts() {
			files = append(files, File{Field: index(index("meshes", i)+".parts", j), Kind: MeshFile, Path: p.GetPath(), Digest: p.GetDigest(),
				SetDigest: func(d string) { p.Digest = d }})
		}
	}
	for i, t := range s.GetTextures() {
		files = append(files, File{Field: index("textures", i), Kind: TextureFile, Path: t.GetPath(), Digest: t.GetDigest(),
			SetDigest: func(d string) { t.Digest = d }})
	}
	return appendGrid(files, "medium.grid", s.GetMedium())
}

// appendGrid appends m's grid file, if m is a grid medium.
func appendGrid(files []File, field string, m *pb.Medium) []File {
	g := m.GetGrid()
	if g == nil {
		return files
	}
	return append(files, File{Field: field, Kind: GridFile, Path: g.GetPath(), Digest: g.GetDigest(),
		SetDigest: func(d string) { g.Digest = d }})
}
