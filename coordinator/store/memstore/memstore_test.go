package memstore_test

import (
	"testing"

	"photonfarm/coordinator/store"
	"photonfarm/coordinator/store/memstore"
	"photonfarm/coordinator/store/storetest"
)

func TestStore(t *testing.T) {
	storetest.Run(t, func(t *testing.T, opts store.Options) store.Store { return memstore.New(opts) })
}

func TestWorkers(t *testing.T) {
	storetest.RunWorkers(t, func(*testing.T) store.Workers { return memstore.NewWorkers() })
}
