package photonmap

import (
	"errors"
	"strconv"

	"photonfarm/coordinator/errs"
)

func asErr(err error, target **errs.Error) bool { return errors.As(err, target) }

func itoa(i int) string { return strconv.Itoa(i) }
