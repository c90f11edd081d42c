package rules

import (
	"crypto/sha256"
	"encoding/hex"
	"hash"
	"regexp"
)

// A content digest is what the digest rule asks of a string and what names a blob:
// "sha256:" and exactly 64 lowercase hex digits. The client and the coordinator's blob
// store make and check digests here, as the worker does in worker/contract/digest.h.

// DigestPattern matches a content digest.
var DigestPattern = regexp.MustCompile(`^sha256:[0-9a-f]{64}$`)

// ValidDigest reports whether d is a content digest.
func ValidDigest(d string) bool { return DigestPattern.MatchString(d) }

// DigestOf returns the content digest of data.
func DigestOf(data []byte) string {
	sum := sha256.Sum256(data)
	return digestText(sum[:])
}

// NewDigestHash returns a hash to stream content through; DigestSum gives its digest.
func NewDigestHash() hash.Hash { return sha256.New() }

// DigestSum returns the content digest of what was written to h, a hash from NewDigestHash.
func DigestSum(h hash.Hash) string { return digestText(h.Sum(nil)) }

func digestText(sum []byte) string { return "sha256:" + hex.EncodeToString(sum) }
