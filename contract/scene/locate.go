package scene

import (
	"bytes"
	"encoding/json"
	"fmt"
	"strconv"

	"google.golang.org/protobuf/reflect/protoreflect"

	"photonfarm/contract/suggest"
)

// misspelling is a name in a scene file that its message or enum does not declare: where
// it is (the field path in .proto names, `shapes[2].sphere.radus`), what it is, and the
// declared name nearest to it, if any is near.
type misspelling struct {
	path, what, name, hint string
}

func (m *misspelling) String() string {
	return fmt.Sprintf("%s: unknown %s %q%s", m.path, m.what, m.name, m.hint)
}

// findMisspelling walks the JSON of a scene along the message descriptors, as protojson
// reads it, and returns the first object key that names no field and the first string
// that names no value of its enum field. It returns nil when there is none, or when the
// JSON is too malformed to walk (protojson's own message says where).
func findMisspelling(data []byte, md protoreflect.MessageDescriptor) *misspelling {
	dec := json.NewDecoder(bytes.NewReader(data))
	dec.UseNumber()
	m, _ := walkMessage(dec, md, "")
	return m
}

// walkMessage reads one JSON value that should be the message md at path.
func walkMessage(dec *json.Decoder, md protoreflect.MessageDescriptor, path string) (*misspelling, error) {
	tok, err := dec.Token()
	if err != nil {
		return nil, err
	}
	if tok != json.Delim('{') {
		return nil, skipRest(dec, tok)
	}
	for dec.More() {
		tok, err := dec.Token()
		if err != nil {
			return nil, err
		}
		key, _ := tok.(string)
		fd := md.Fields().ByJSONName(key)
		if fd == nil {
			fd = md.Fields().ByName(protoreflect.Name(key))
		}
		if fd == nil {
			return &misspelling{path: join(path, key), what: "field", name: key, hint: suggest.Hint(key, fieldNames(md))}, nil
		}
		if m, err := walkField(dec, fd, join(path, string(fd.Name()))); m != nil || err != nil {
			return m, err
		}
	}
	_, err = dec.Token() // '}'
	return nil, err
}

// walkField reads the JSON value of field fd at path.
func walkField(dec *json.Decoder, fd protoreflect.FieldDescriptor, path string) (*misspelling, error) {
	if !fd.IsList() && !fd.IsMap() {
		return walkSingle(dec, fd, path)
	}
	tok, err := dec.Token()
	if err != nil {
		return nil, err
	}
	open := json.Delim('[')
	if fd.IsMap() {
		open = json.Delim('{')
	}
	if tok != open {
		return nil, skipRest(dec, tok)
	}
	for i := 0; dec.More(); i++ {
		at, value := path+"["+strconv.Itoa(i)+"]", fd
		if fd.IsMap() {
			key, err := dec.Token()
			if err != nil {
				return nil, err
			}
			at, value = fmt.Sprintf("%s[%q]", path, key), fd.MapValue()
		}
		if m, err := walkSingle(dec, value, at); m != nil || err != nil {
			return m, err
		}
	}
	_, err = dec.Token() // ']' or '}'
	return nil, err
}

// walkSingle reads one value of fd's kind (one element, for a list or a map).
func walkSingle(dec *json.Decoder, fd protoreflect.FieldDescriptor, path string) (*misspelling, error) {
	switch fd.Kind() {
	case protoreflect.MessageKind, protoreflect.GroupKind:
		if fd.Message().FullName().Parent() == "google.protobuf" {
			return nil, skipValue(dec) // well-known types have JSON forms of their own
		}
		return walkMessage(dec, fd.Message(), path)
	case protoreflect.EnumKind:
		tok, err := dec.Token()
		if err != nil {
			return nil, err
		}
		name, isName := tok.(string)
		if isName && fd.Enum().Values().ByName(protoreflect.Name(name)) == nil {
			return &misspelling{path: path, what: "value", name: name, hint: suggest.Hint(name, enumNames(fd.Enum()))}, nil
		}
		return nil, skipRest(dec, tok)
	}
	return nil, skipValue(dec)
}

// skipValue reads one whole JSON value.
func skipValue(dec *json.Decoder) error {
	tok, err := dec.Token()
	if err != nil {
		return err
	}
	return skipRest(dec, tok)
}

// skipRest reads the rest of the value that began with tok.
func skipRest(dec *json.Decoder, tok json.Token) error {
	if tok != json.Delim('{') && tok != json.Delim('[') {
		return nil
	}
	for depth := 1; depth > 0; {
		t, err := dec.Token()
		if err != nil {
			return err
		}
		switch t {
		case json.Delim('{'), json.Delim('['):
			depth++
		case json.Delim('}'), json.Delim(']'):
			depth--
		}
	}
	return nil
}

func join(path, name string) string {
	if path == "" {
		return name
	}
	return path + "." + name
}

// fieldNames lists md's fields by the names scene files use (the JSON names, as the
// project's scenes do).
func fieldNames(md protoreflect.MessageDescriptor) []string {
	fs := md.Fields()
	names := make([]string, fs.Len())
	for i := range names {
		names[i] = fs.Get(i).JSONName()
	}
	return names
}

func enumNames(ed protoreflect.EnumDescriptor) []string {
	vs := ed.Values()
	names := make([]string, vs.Len())
	for i := range names {
		names[i] = string(vs.Get(i).Name())
	}
	return names
}
