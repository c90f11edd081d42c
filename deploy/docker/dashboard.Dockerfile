# The web dashboard: the same static farm binary. It holds no token; browsers log in with
# a client token.
FROM debian:bookworm-slim
RUN groupadd --system --gid 10001 farm \
 && useradd --system --uid 10001 --gid farm --no-create-home --shell /usr/sbin/nologin farm
COPY .build/farm /usr/local/bin/farm
USER farm
EXPOSE 8080
# bash's /dev/tcp stands in for curl: healthy when GET /api/session answers HTTP.
HEALTHCHECK --interval=5s --timeout=3s --retries=6 CMD ["bash", "-c", \
  "exec 3<>/dev/tcp/127.0.0.1/8080 && printf 'GET /api/session HTTP/1.0\\r\\n\\r\\n' >&3 && head -n1 <&3 | grep -q '^HTTP/1.[01] [24]'"]
ENTRYPOINT ["farm", "dashboard"]
CMD ["--listen", ":8080", "--coordinator", "coordinator:7070", "--insecure"]
