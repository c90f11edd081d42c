# The coordinator: the static farm binary (built on the host, see build-images.sh) and an
# entrypoint that turns the token variables into token files.
FROM debian:bookworm-slim
RUN groupadd --system --gid 10001 farm \
 && useradd --system --uid 10001 --gid farm --home-dir /var/lib/farm --shell /usr/sbin/nologin farm \
 && install -d -o farm -g farm -m 0750 /var/lib/farm /run/farm
COPY .build/farm /usr/local/bin/farm
COPY docker/coordinator-entrypoint.sh /usr/local/bin/coordinator-entrypoint
USER farm
VOLUME /var/lib/farm
EXPOSE 7070 9090
# Healthy once the coordinator answers an authenticated ListJobs (which also reads Redis).
HEALTHCHECK --interval=5s --timeout=5s --start-period=5s --retries=6 \
  CMD FARM_TOKEN="$(head -n1 /run/farm/client-tokens)" farm list --coordinator 127.0.0.1:7070 >/dev/null || exit 1
ENTRYPOINT ["/usr/local/bin/coordinator-entrypoint"]
CMD ["--listen", ":7070", "--metrics-listen", ":9090", "--data-dir", "/var/lib/farm"]
