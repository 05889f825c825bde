#!/bin/sh
# claims.sh - tests/claims.csv, the figures the manuals promise: each page
# states each figure in the section named, each command measures it within
# its tolerance, each unit-test figure is named by its test (which asserts
# it: ASSERT_CLAIM).  tests/claims_check does the work (tests/claims.h).
: "${top_srcdir:?top_srcdir must name the source directory}"
CLAIMS_TMP=$(mktemp -d "${TMPDIR:-/tmp}/seabake-claims.XXXXXX") || exit 99
export CLAIMS_TMP
trap 'rm -rf "$CLAIMS_TMP"' EXIT
./tests/claims_check "$top_srcdir/tests/claims.csv"
