package scene

import (
	"fmt"
	"math"
	"regexp"
	"strconv"

	pb "photonfarm/proto/renderfarm/v1"
)

// FieldError says which field of a scene is wrong and why.
type FieldError struct {
	// Field is a protobuf-style path with the .proto field names: "shapes[2].sphere.radius".
	Field string
	// Message says what is wrong: "must be > 0, got -1".
	Message string
}

func (e *FieldError) Error() string { return e.Field + ": " + e.Message }

// DigestPattern matches a content digest: "sha256:" and 64 lowercase hex digits.
var DigestPattern = regexp.MustCompile(`^sha256:[0-9a-f]{64}$`)

// Validate checks every field of s against the rules and limits of the contract
// (scene.proto, docs/limits.md) and returns the first violation as a *FieldError, or nil.
func Validate(s *pb.Scene) error {
	if s == nil {
		return &FieldError{Field: "scene", Message: "missing"}
	}
	if err := checkName("name", s.GetName()); err != nil {
		return err
	}
	if err := validateCamera(s.GetCamera()); err != nil {
		return err
	}
	if err := validateFilm(s.GetFilm()); err != nil {
		return err
	}
	if n := s.GetSampling().GetSamplesPerPixel(); n > MaxSamplesPerPixel {
		return fe("sampling.samples_per_pixel", "must be <= %d, got %d", MaxSamplesPerPixel, n)
	}
	emissive, err := validateMaterials(s.GetMaterials())
	if err != nil {
		return err
	}
	lights, err := validateLights(s.GetLights())
	if err != nil {
		return err
	}
	areaLights, err := validateShapes(s.GetShapes(), emissive)
	if err != nil {
		return err
	}
	if lights+areaLights == 0 {
		return fe("lights", "the scene needs a light: a point or sun light with a positive power, "+
			"or a shape whose material is emissive with a positive radiance")
	}
	if err := validatePhotons(s.GetPhotons()); err != nil {
		return err
	}
	return validateRendering(s)
}

func fe(field, format string, args ...any) *FieldError {
	return &FieldError{Field: field, Message: fmt.Sprintf(format, args...)}
}

func idx(list string, i int) string { return list + "[" + strconv.Itoa(i) + "]" }

func fmtNum(v float64) string { return strconv.FormatFloat(v, 'g', -1, 64) }

func checkName(field, name string) error {
	if len(name) > MaxNameLength {
		return fe(field, "must be at most %d bytes, got %d", MaxNameLength, len(name))
	}
	return nil
}

// checkFinite refuses NaN, infinities and magnitudes past MaxCoordinate.
func checkFinite(field string, v float64) error {
	if math.IsNaN(v) || math.IsInf(v, 0) {
		return fe(field, "must be a finite number, got %s", fmtNum(v))
	}
	if math.Abs(v) > MaxCoordinate {
		return fe(field, "must be within ±%s, got %s", fmtNum(MaxCoordinate), fmtNum(v))
	}
	return nil
}

type vec struct{ x, y, z float64 }

func (a vec) sub(b vec) vec { return vec{a.x - b.x, a.y - b.y, a.z - b.z} }
func (a vec) add(b vec) vec { return vec{a.x + b.x, a.y + b.y, a.z + b.z} }
func (a vec) scale(k float64) vec {
	return vec{a.x * k, a.y * k, a.z * k}
}
func (a vec) cross(b vec) vec { return vec{a.y*b.z - a.z*b.y, a.z*b.x - a.x*b.z, a.x*b.y - a.y*b.x} }
func (a vec) length() float64 { return math.Sqrt(a.x*a.x + a.y*a.y + a.z*a.z) }
func (a vec) isZero() bool    { return a.x == 0 && a.y == 0 && a.z == 0 }
func (a vec) String() string {
	return "(" + fmtNum(a.x) + ", " + fmtNum(a.y) + ", " + fmtNum(a.z) + ")"
}
func toVec(v *pb.Vec3) vec   { return vec{v.GetX(), v.GetY(), v.GetZ()} }
func parallel(a, b vec) bool { return a.cross(b).length() <= 1e-9*a.length()*b.length() }
func requiredVec3(field string, v *pb.Vec3) (vec, error) {
	if v == nil {
		return vec{}, fe(field, "missing")
	}
	return finiteVec3(field, v)
}

func finiteVec3(field string, v *pb.Vec3) (vec, error) {
	for _, c := range []struct {
		n string
		v float64
	}{{"x", v.GetX()}, {"y", v.GetY()}, {"z", v.GetZ()}} {
		if err := checkFinite(field+"."+c.n, c.v); err != nil {
			return vec{}, err
		}
	}
	return toVec(v), nil
}

func validateCamera(c *pb.Camera) error {
	if c == nil {
		return fe("camera", "missing")
	}
	pos, err := requiredVec3("camera.position", c.GetPosition())
	if err != nil {
		return err
	}
	at, err := requiredVec3("camera.look_at", c.GetLookAt())
	if err != nil {
		return err
	}
	up, err := requiredVec3("camera.up", c.GetUp())
	if err != nil {
		return err
	}
	view := at.sub(pos)
	if view.isZero() {
		return fe("camera.look_at", "must differ from camera.position, both are %s", pos)
	}
	if up.isZero() {
		return fe("camera.up", "must be non-zero")
	}
	if parallel(view, up) {
		return fe("camera.up", "must not be parallel to the view direction look_at - position = %s, got %s", view, up)
	}
	fov := c.GetVerticalFovDegrees()
	if err := checkFinite("camera.vertical_fov_degrees", fov); err != nil {
		return err
	}
	if fov <= 0 || fov >= 180 {
		return fe("camera.vertical_fov_degrees", "must be in (0, 180), got %s", fmtNum(fov))
	}
	return nil
}

func validateFilm(f *pb.Film) error {
	if f == nil {
		return fe("film", "missing")
	}
	if w := f.GetWidth(); w < 1 || w > MaxFilmSide {
		return fe("film.width", "must be in [1, %d], got %d", MaxFilmSide, w)
	}
	if h := f.GetHeight(); h < 1 || h > MaxFilmSide {
		return fe("film.height", "must be in [1, %d], got %d", MaxFilmSide, h)
	}
	if t := f.GetTileSize(); t != 0 && (t < MinTileSize || t > MaxTileSize) {
		return fe("film.tile_size", "must be 0 (default %d) or in [%d, %d], got %d", DefaultTileSize, MinTileSize, MaxTileSize, t)
	}
	return nil
}

// validateMaterials returns, by name, whether each material emits light.
func validateMaterials(ms []*pb.Material) (map[string]bool, error) {
	if len(ms) > MaxMaterials {
		return nil, fe("materials", "must have at most %d entries, got %d", MaxMaterials, len(ms))
	}
	emissive := make(map[string]bool, len(ms))
	for i, m := range ms {
		p := idx("materials", i)
		switch {
		case m.GetName() == "":
			return nil, fe(p+".name", "must be non-empty")
		case len(m.GetName()) > MaxNameLength:
			return nil, checkName(p+".name", m.GetName())
		}
		if _, dup := emissive[m.GetName()]; dup {
			return nil, fe(p+".name", "duplicate material name %q", m.GetName())
		}
		emits := false
		switch k := m.GetKind().(type) {
		case *pb.Material_Lambert:
			if err := checkColor(p+".lambert.reflectance", k.Lambert.GetReflectance(), 1); err != nil {
				return nil, err
			}
		case *pb.Material_Emissive:
			rad := k.Emissive.GetRadiance()
			if err := checkColor(p+".emissive.radiance", rad, math.Inf(1)); err != nil {
				return nil, err
			}
			emits = rad.GetR() > 0 || rad.GetG() > 0 || rad.GetB() > 0
		case nil:
			return nil, fe(p, "exactly one kind (lambert, emissive, glossy, mirror, dielectric, conductor) must be set")
		default:
			if err := validateSurface(p, m); err != nil {
				return nil, err
			}
		}
		emissive[m.GetName()] = emits
	}
	return emissive, nil
}

// checkColor requires c present, finite and each component in [0, max].
func checkColor(field string, c *pb.Color, max float64) error {
	if c == nil {
		return fe(field, "missing")
	}
	for _, comp := range []struct {
		n string
		v float64
	}{{"r", c.GetR()}, {"g", c.GetG()}, {"b", c.GetB()}} {
		f := field + "." + comp.n
		if err := checkFinite(f, comp.v); err != nil {
			return err
		}
		if comp.v < 0 {
			return fe(f, "must be >= 0, got %s", fmtNum(comp.v))
		}
		if comp.v > max {
			return fe(f, "must be <= %s, got %s", fmtNum(max), fmtNum(comp.v))
		}
	}
	return nil
}

// validateShapes returns the number of shapes that are area lights.
func validateShapes(shapes []*pb.Shape, emissive map[string]bool) (int, error) {
	if len(shapes) > MaxShapes {
		return 0, fe("shapes", "must have at most %d entries, got %d", MaxShapes, len(shapes))
	}
	lights := 0
	for i, s := range shapes {
		p := idx("shapes", i)
		if err := checkName(p+".name", s.GetName()); err != nil {
			return 0, err
		}
		if s.GetMaterial() == "" {
			return 0, fe(p+".material", "must name a material")
		}
		emits, ok := emissive[s.GetMaterial()]
		if !ok {
			return 0, fe(p+".material", "no material named %q", s.GetMaterial())
		}
		if emits {
			lights++
		}
		var err error
		switch g := s.GetGeometry().(type) {
		case *pb.Shape_Sphere:
			err = validateSphere(p+".sphere", g.Sphere)
		case *pb.Shape_Quad:
			err = validateQuad(p+".quad", g.Quad)
		case *pb.Shape_Triangles:
			err = validateTriangles(p+".triangles", g.Triangles)
		case *pb.Shape_Mesh:
			err = validateMesh(p+".mesh", g.Mesh)
		default:
			err = fe(p, "exactly one geometry (sphere, quad, triangles, mesh) must be set")
		}
		if err != nil {
			return 0, err
		}
	}
	return lights, nil
}

func validateSphere(p string, s *pb.Sphere) error {
	if _, err := requiredVec3(p+".center", s.GetCenter()); err != nil {
		return err
	}
	r := s.GetRadius()
	if err := checkFinite(p+".radius", r); err != nil {
		return err
	}
	if r <= 0 {
		return fe(p+".radius", "must be > 0, got %s", fmtNum(r))
	}
	return nil
}

func validateQuad(p string, q *pb.Quad) error {
	if _, err := requiredVec3(p+".origin", q.GetOrigin()); err != nil {
		return err
	}
	u, err := requiredVec3(p+".edge_u", q.GetEdgeU())
	if err != nil {
		return err
	}
	v, err := requiredVec3(p+".edge_v", q.GetEdgeV())
	if err != nil {
		return err
	}
	if u.isZero() {
		return fe(p+".edge_u", "must be non-zero")
	}
	if v.isZero() {
		return fe(p+".edge_v", "must be non-zero")
	}
	if parallel(u, v) {
		return fe(p+".edge_v", "must not be parallel to edge_u %s, got %s", u, v)
	}
	return nil
}

func validateTriangles(p string, t *pb.TriangleMesh) error {
	pos, ind := t.GetPositions(), t.GetIndices()
	if len(pos) > MaxMeshPositions {
		return fe(p+".positions", "must have at most %d items, got %d", MaxMeshPositions, len(pos))
	}
	if len(ind) > MaxMeshIndices {
		return fe(p+".indices", "must have at most %d items, got %d", MaxMeshIndices, len(ind))
	}
	if len(pos) < 3 {
		return fe(p+".positions", "must have at least 3 items, got %d", len(pos))
	}
	if len(ind) == 0 || len(ind)%3 != 0 {
		return fe(p+".indices", "count must be a non-zero multiple of 3, got %d", len(ind))
	}
	for i, v := range pos {
		if _, err := requiredVec3(idx(p+".positions", i), v); err != nil {
			return err
		}
	}
	for i, v := range ind {
		if int(v) >= len(pos) {
			return fe(idx(p+".indices", i), "must be < %d (the number of positions), got %d", len(pos), v)
		}
	}
	return nil
}

func validateMesh(p string, m *pb.MeshFile) error {
	switch d := m.GetDigest(); {
	case d == "" && m.GetPath() != "":
		return fe(p+".digest", "missing; clients upload the file named by path and set its digest")
	case d == "":
		return fe(p+".digest", "missing")
	case !DigestPattern.MatchString(d):
		return fe(p+".digest", "must be \"sha256:\" followed by 64 lowercase hex digits, got %q", d)
	}
	if len(m.GetPath()) > MaxPathLength {
		return fe(p+".path", "must be at most %d bytes, got %d", MaxPathLength, len(m.GetPath()))
	}
	tr := m.GetTransform()
	if tr == nil {
		return nil
	}
	tp := p + ".transform"
	if _, err := finiteVec3(tp+".translation", tr.GetTranslation()); err != nil {
		return err
	}
	if tr.GetScale() != nil {
		sc, err := finiteVec3(tp+".scale", tr.GetScale())
		if err != nil {
			return err
		}
		for _, c := range []struct {
			n string
			v float64
		}{{"x", sc.x}, {"y", sc.y}, {"z", sc.z}} {
			if c.v == 0 {
				return fe(tp+".scale."+c.n, "must be non-zero")
			}
		}
	}
	axis, err := finiteVec3(tp+".rotation_axis", tr.GetRotationAxis())
	if err != nil {
		return err
	}
	deg := tr.GetRotationDegrees()
	if err := checkFinite(tp+".rotation_degrees", deg); err != nil {
		return err
	}
	if deg != 0 && axis.isZero() {
		return fe(tp+".rotation_axis", "must be non-zero when rotation_degrees is %s", fmtNum(deg))
	}
	return nil
}
