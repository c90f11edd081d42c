package service

import (
	"crypto/rand"
	"crypto/sha256"
	"crypto/subtle"
	"encoding/hex"
)

// Limits of the worker registry (docs/limits.md; store.MaxWorkers bounds its size).
const (
	// ForgetAfterLeases: a worker not heard from for this many lease durations is
	// forgotten (its leases expired long before); if it comes back, its next heartbeat
	// or lease gets NOT_FOUND and it registers again.
	ForgetAfterLeases = 4
)

// Page sizes of ListWorkers (job.proto).
const (
	DefaultWorkersPage = 100
	MaxWorkersPage     = 1000
)

// Worker ids and secrets. A worker's id is derived from the secret its registration
// answered, so that any replica can check a call's pair without having seen the
// registration; the registry itself is store.Workers.

// newWorkerSecret returns a fresh registration secret and the worker id it makes.
func newWorkerSecret() (secret, id string) {
	var b [32]byte
	_, _ = rand.Read(b[:])
	secret = hex.EncodeToString(b[:])
	return secret, workerIDOf(secret)
}

// workerIDOf is the id a registration secret makes: 96 bits of its SHA-256, so that an id
// cannot be turned back into its secret, and any coordinator can check a pair without
// having seen the registration.
func workerIDOf(secret string) string {
	sum := sha256.Sum256([]byte("photonfarm worker id\x00" + secret))
	return "w-" + hex.EncodeToString(sum[:12])
}

// secretFits reports whether secret is the one id was made from, in constant time.
func secretFits(id, secret string) bool {
	return subtle.ConstantTimeCompare([]byte(workerIDOf(secret)), []byte(id)) == 1
}
