# The farm's object store: SeaweedFS's weed (Apache-2.0), every service of a one-machine
# SeaweedFS in one process (`weed mini`), built on the host by scripts/install-deps.sh from
# the Go module scripts/seaweedfs.version pins, and copied in like the farm's binaries.
# Only its S3 port is used; the coordinators keep their blobs in its bucket.
FROM debian:bookworm-slim
RUN groupadd --system --gid 10002 weed \
 && useradd --system --uid 10002 --gid weed --home-dir /data --shell /usr/sbin/nologin weed \
 && install -d -o weed -g weed -m 0750 /data /run/weed
COPY .build/weed /usr/local/bin/weed
COPY docker/objectstore-entrypoint.sh /usr/local/bin/objectstore-entrypoint
USER weed
WORKDIR /data
VOLUME /data
EXPOSE 8333
# Healthy once the S3 gateway answers (bash's /dev/tcp: the image has no curl). The bucket
# comes a moment later; a coordinator that starts before it exits and is restarted.
HEALTHCHECK --interval=2s --timeout=3s --start-period=5s --retries=30 \
  CMD ["bash", "-c", "exec 3<>/dev/tcp/127.0.0.1/8333 && printf 'GET /healthz HTTP/1.0\\r\\n\\r\\n' >&3 && head -n1 <&3 | grep -q ' 200 '"]
ENTRYPOINT ["/usr/local/bin/objectstore-entrypoint"]
