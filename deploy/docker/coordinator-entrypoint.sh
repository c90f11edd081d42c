#!/bin/sh
# Writes $FARM_CLIENT_TOKEN and $FARM_WORKER_TOKEN (comma-separated lists) into token files
# readable only by the farm user, drops the variables and starts the coordinator on them.
# An empty list stops here: a token file with no token is refused, so a forgotten setting
# cannot turn authentication off.
set -eu
umask 077
for role in client worker; do
  case $role in
    client) tokens=${FARM_CLIENT_TOKEN:-} ;;
    worker) tokens=${FARM_WORKER_TOKEN:-} ;;
  esac
  if [ -z "$tokens" ]; then
    echo "coordinator-entrypoint: FARM_$(echo $role | tr a-z A-Z)_TOKEN is empty (set it in deploy/.env)" >&2
    exit 2
  fi
  printf '%s\n' "$tokens" | tr ',' '\n' > "/run/farm/$role-tokens"
done
unset FARM_CLIENT_TOKEN FARM_WORKER_TOKEN FARM_CLIENT_TOKENS FARM_WORKER_TOKENS
exec farm coordinator --client-token-file /run/farm/client-tokens \
  --worker-token-file /run/farm/worker-tokens "$@"
