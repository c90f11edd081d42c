package rules

import (
	"fmt"
	"math"
	"slices"
	"strconv"
	"strings"
	"sync"

	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/reflect/protoreflect"

	pb "photonfarm/proto/renderfarm/v1"
)

// FieldError says which field of a message is wrong and why.
type FieldError struct {
	// Field is a path of .proto field names from the checked message: "shapes[2].sphere.radius".
	Field string
	// Message says what is wrong: "must be > 0, got -1".
	Message string
}

func (e *FieldError) Error() string { return e.Field + ": " + e.Message }

// Errorf returns a *FieldError for field.
func Errorf(field, format string, args ...any) *FieldError {
	return &FieldError{Field: field, Message: fmt.Sprintf(format, args...)}
}

// Check returns the first field of m that breaks its rule, or nil: fields in declaration
// order, depth first, each message's required oneofs after its fields. Only set messages
// are entered, and of a oneof only its set member. The worker's check walks in the same
// order with the same messages (worker/contract/rules.cpp).
func Check(m proto.Message) *FieldError {
	return checkMessage(m.ProtoReflect(), nil)
}

// The walk makes an error with the path below the value it checks and each level puts its
// own part in front on the way out (under), so that a path is spelled out only for an
// error and a large list costs no strings.

func fail(format string, args ...any) *FieldError { return Errorf("", format, args...) }

// under returns err, found in part ("name" of a field, or "[3]" of an element), with part
// in front of its path.
func under(part string, err *FieldError) *FieldError {
	switch {
	case err.Field == "" || err.Field[0] == '[':
		err.Field = part + err.Field
	default:
		err.Field = part + "." + err.Field
	}
	return err
}

// checkMessage checks msg; inherited is the rule of the field that holds it when that
// rule bounds the components of a value message (Color, Vec3).
func checkMessage(msg protoreflect.Message, inherited *pb.FieldRule) *FieldError {
	md := msg.Descriptor()
	for i := 0; i < md.Fields().Len(); i++ {
		fd := md.Fields().Get(i)
		if fd.ContainingOneof() != nil && !msg.Has(fd) {
			continue
		}
		r := cachedRule(fd)
		if r == noRule && inherited != nil && isNumber(fd) {
			r = inherited
		}
		if err := checkField(msg, fd, r); err != nil {
			return under(string(fd.Name()), err)
		}
	}
	for i := 0; i < md.Oneofs().Len(); i++ {
		od := md.Oneofs().Get(i)
		if OneRequired(od) && msg.WhichOneof(od) == nil {
			names := make([]string, od.Fields().Len())
			for j := range names {
				names[j] = string(od.Fields().Get(j).Name())
			}
			return fail("exactly one of %s must be set", strings.Join(names, ", "))
		}
	}
	return nil
}

// noRule stands for the rule of a field that declares none, so that checks read one.
var noRule = &pb.FieldRule{}

var ruleCache sync.Map // protoreflect.FieldDescriptor -> *pb.FieldRule

// cachedRule is Of(fd), or noRule, read from the descriptor once.
func cachedRule(fd protoreflect.FieldDescriptor) *pb.FieldRule {
	if r, ok := ruleCache.Load(fd); ok {
		return r.(*pb.FieldRule)
	}
	r := Of(fd)
	if r == nil {
		r = noRule
	}
	ruleCache.Store(fd, r)
	return r
}

func checkField(msg protoreflect.Message, fd protoreflect.FieldDescriptor, r *pb.FieldRule) *FieldError {
	switch {
	case fd.IsMap():
		// In key order, as the worker checks them: the first error is the same on both sides.
		m := msg.Get(fd).Map()
		var keys []protoreflect.MapKey
		m.Range(func(k protoreflect.MapKey, _ protoreflect.Value) bool {
			keys = append(keys, k)
			return true
		})
		slices.SortFunc(keys, func(a, b protoreflect.MapKey) int { return strings.Compare(a.String(), b.String()) })
		for _, k := range keys {
			if len(r.GetKeys()) > 0 && !slices.Contains(r.GetKeys(), k.String()) {
				return under("["+k.String()+"]", fail("is not a key it may have (%s)", strings.Join(r.GetKeys(), ", ")))
			}
			if err := checkValue(fd.MapValue(), m.Get(k), r); err != nil {
				return under("["+k.String()+"]", err)
			}
		}
		return nil
	case fd.IsList():
		list := msg.Get(fd).List()
		n := uint64(list.Len())
		if r.MaxItems != nil && n > r.GetMaxItems() {
			return fail("must have at most %d entries, got %d", r.GetMaxItems(), n)
		}
		if r.MinItems != nil && n < r.GetMinItems() {
			return fail("must have at least %d entries, got %d", r.GetMinItems(), n)
		}
		for i := 0; i < list.Len(); i++ {
			if err := checkValue(fd, list.Get(i), r); err != nil {
				return under("["+strconv.Itoa(i)+"]", err)
			}
		}
		return nil
	case fd.Kind() == protoreflect.MessageKind:
		if !msg.Has(fd) {
			if r.GetRequired() {
				return fail("missing")
			}
			return nil
		}
	}
	return checkValue(fd, msg.Get(fd), r)
}

// checkValue checks one value of field fd (the field's value, or one element of a list or
// map) against r.
func checkValue(fd protoreflect.FieldDescriptor, v protoreflect.Value, r *pb.FieldRule) *FieldError {
	switch fd.Kind() {
	case protoreflect.MessageKind, protoreflect.GroupKind:
		var components *pb.FieldRule
		if hasBounds(r) {
			components = r
		}
		return checkMessage(v.Message(), components)
	case protoreflect.StringKind:
		return checkString(v.String(), r)
	case protoreflect.BytesKind:
		return checkString(string(v.Bytes()), r)
	case protoreflect.EnumKind:
		if fd.Enum().Values().ByNumber(v.Enum()) == nil {
			return fail("unknown %s value %d", fd.Enum().Name(), v.Enum())
		}
		return nil
	case protoreflect.BoolKind:
		return nil
	case protoreflect.FloatKind, protoreflect.DoubleKind:
		f := v.Float()
		if math.IsNaN(f) || math.IsInf(f, 0) {
			return fail("must be a finite number, got %s", Number(f))
		}
		if limit := Scene.GetMaxMagnitude(); math.Abs(f) > limit {
			return fail("must be within ±%s, got %s", Number(limit), Number(f))
		}
		return checkBounds(f, v, r)
	case protoreflect.Uint32Kind, protoreflect.Uint64Kind, protoreflect.Fixed32Kind, protoreflect.Fixed64Kind:
		return checkBounds(float64(v.Uint()), v, r)
	default: // signed integers
		return checkBounds(float64(v.Int()), v, r)
	}
}

func checkString(s string, r *pb.FieldRule) *FieldError {
	n := len(s)
	if r.GetRequired() && n == 0 {
		return fail("missing")
	}
	if r.MaxBytes != nil && uint64(n) > r.GetMaxBytes() {
		return fail("must be at most %d bytes, got %d", r.GetMaxBytes(), n)
	}
	if r.GetDigest() && n > 0 && !DigestPattern.MatchString(s) {
		return fail("must be \"sha256:\" followed by 64 lowercase hex digits, got %q", Truncate(s, 80))
	}
	return nil
}

// checkBounds checks number v (the value of raw, shown as it is written) against r's
// bounds; 0 passes when r has a default, which it selects.
func checkBounds(v float64, raw protoreflect.Value, r *pb.FieldRule) *FieldError {
	if !hasBounds(r) || (v == 0 && r.DefaultValue != nil) {
		return nil
	}
	ok := (r.Gte == nil || v >= r.GetGte()) && (r.Gt == nil || v > r.GetGt()) &&
		(r.Lte == nil || v <= r.GetLte()) && (r.Lt == nil || v < r.GetLt())
	if ok {
		return nil
	}
	var shown string
	switch x := raw.Interface().(type) {
	case float64:
		shown = Number(x)
	case float32:
		shown = Number(float64(x))
	default: // an integer, in full
		shown = fmt.Sprint(x)
	}
	return fail("%s, got %s", Describe(r), shown)
}

// Describe says in words what numbers r allows: "must be in [8, 256] (0 selects 32)", or
// "" when r (which may be nil) has no bounds.
func Describe(r *pb.FieldRule) string {
	if !hasBounds(r) {
		return ""
	}
	lo, loOpen := bound(r.Gt, r.Gte)
	hi, hiOpen := bound(r.Lt, r.Lte)
	var s string
	switch {
	case lo != "" && hi != "":
		s = "must be in " + pick(loOpen, "(", "[") + lo + ", " + hi + pick(hiOpen, ")", "]")
	case lo != "":
		s = "must be " + pick(loOpen, "> ", ">= ") + lo
	default:
		s = "must be " + pick(hiOpen, "< ", "<= ") + hi
	}
	if r.DefaultValue != nil {
		s += " (0 selects " + Number(r.GetDefaultValue()) + ")"
	}
	return s
}

// bound returns the bound an exclusive or an inclusive limit sets, if either is set, and
// whether it is exclusive.
func bound(exclusive, inclusive *float64) (string, bool) {
	switch {
	case exclusive != nil:
		return Number(*exclusive), true
	case inclusive != nil:
		return Number(*inclusive), false
	}
	return "", false
}

func pick(c bool, yes, no string) string {
	if c {
		return yes
	}
	return no
}

func hasBounds(r *pb.FieldRule) bool {
	return r != nil && (r.Gte != nil || r.Gt != nil || r.Lte != nil || r.Lt != nil)
}

func isNumber(fd protoreflect.FieldDescriptor) bool {
	switch fd.Kind() {
	case protoreflect.FloatKind, protoreflect.DoubleKind, protoreflect.Int32Kind, protoreflect.Int64Kind,
		protoreflect.Uint32Kind, protoreflect.Uint64Kind, protoreflect.Sint32Kind, protoreflect.Sint64Kind,
		protoreflect.Fixed32Kind, protoreflect.Fixed64Kind, protoreflect.Sfixed32Kind, protoreflect.Sfixed64Kind:
		return true
	}
	return false
}

// Number formats v as briefly as it round-trips, but whole numbers below a billion in
// full: 16384, 50000000, 0.1, 1e+12.
func Number(v float64) string {
	if v == math.Trunc(v) && math.Abs(v) < 1e9 {
		return strconv.FormatFloat(v, 'f', -1, 64)
	}
	return strconv.FormatFloat(v, 'g', -1, 64)
}

// Truncate cuts s to at most n bytes (on a rune boundary), marking the cut, so that a
// hostile value is not echoed back whole.
func Truncate(s string, n int) string {
	if len(s) <= n {
		return s
	}
	for n > 0 && !utf8RuneStart(s[n]) {
		n--
	}
	return s[:n] + "…"
}

func utf8RuneStart(b byte) bool { return b&0xC0 != 0x80 }
