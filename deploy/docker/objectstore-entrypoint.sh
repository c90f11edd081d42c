#!/bin/sh
# Writes the one S3 identity ($FARM_S3_ACCESS_KEY, $FARM_S3_SECRET_KEY) into weed's S3
# config, readable only by the weed user, drops the variables and starts `weed mini` with
# the bucket $FARM_S3_BUCKET. Empty keys stop here: weed without identities would let
# anyone on the network read and write every blob.
set -eu
umask 077
: "${FARM_S3_BUCKET:=farm}"
if [ -z "${FARM_S3_ACCESS_KEY:-}" ] || [ -z "${FARM_S3_SECRET_KEY:-}" ]; then
  echo "objectstore-entrypoint: FARM_S3_ACCESS_KEY or FARM_S3_SECRET_KEY is empty (set them in deploy/.env)" >&2
  exit 2
fi
printf '{"identities":[{"name":"farm","credentials":[{"accessKey":"%s","secretKey":"%s"}],"actions":["Admin","Read","Write","List","Tagging"]}]}\n' \
  "$FARM_S3_ACCESS_KEY" "$FARM_S3_SECRET_KEY" > /run/weed/s3.json
unset FARM_S3_ACCESS_KEY FARM_S3_SECRET_KEY
# weed's services talk to each other over 127.0.0.1; the farm reaches only the S3 port,
# 8333. (weed mini has one bind address, so its other ports listen on the compose network
# too, which only the farm's own containers are on; none is published.)
exec weed mini -dir=/data -ip=127.0.0.1 -ip.bind=0.0.0.0 \
  -master.telemetry=false -webdav=false -admin.ui=false \
  -s3.port=8333 -s3.port.iceberg=0 -s3.port.lance=0 \
  -s3.config=/run/weed/s3.json -bucket="$FARM_S3_BUCKET" "$@"
