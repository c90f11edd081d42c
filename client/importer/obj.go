package importer

import (
	"context"
	"errors"
)

func importOBJ(ctx context.Context, src string, w *writer, opt Options) (*Result, error) {
	return nil, errors.New("OBJ import is not written yet")
}
