# A render worker: the C++ farm-worker built on the host (bookworm, like this image) and
# only the runtime libraries it links (readelf -d build/bin/farm-worker | grep NEEDED).
FROM debian:bookworm-slim
RUN apt-get update \
 && apt-get install -y --no-install-recommends \
      libembree3-3 libtbb12 libgrpc++1.51 libgrpc29 libprotobuf32 libabsl20220623 libssl3 \
      libopenexr-3-1-30 libopenimageio2.4 libtinyobjloader2rc10 \
 && rm -rf /var/lib/apt/lists/* \
 && groupadd --system --gid 10001 farm \
 && useradd --system --uid 10001 --gid farm --home-dir /var/cache/farm-worker --shell /usr/sbin/nologin farm \
 && install -d -o farm -g farm -m 0750 /var/cache/farm-worker
COPY .build/farm-worker /usr/local/bin/farm-worker
# Fails at build time if a library is missing.
RUN ! ldd /usr/local/bin/farm-worker | grep 'not found'
USER farm
# Healthy while the worker process runs and the coordinator is reachable.
HEALTHCHECK --interval=10s --timeout=3s --retries=3 CMD ["bash", "-c", \
  "kill -0 1 && exec 3<>/dev/tcp/${FARM_COORDINATOR_HOST:-coordinator}/${FARM_COORDINATOR_PORT:-7070}"]
ENTRYPOINT ["farm-worker", "--cache-dir", "/var/cache/farm-worker"]
CMD ["--coordinator", "coordinator:7070", "--insecure"]
