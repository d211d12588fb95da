# The first line of a benchmark's JSON output: what ran, where and when.
# Sourced by the scripts in bench/.
#
#   bench_header NAME COMMAND [EXTRA]
#     EXTRA: more fields, as JSON text that begins with ", "
# YV_COMMIT names the commit where the working tree's git history is not the
# one built. The load average says how much else the machine was doing
# (timings on a shared machine are only comparable at a similar load).
bench_header() {
    local name=$1 command=$2 extra=${3:-} root gpu
    root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
    gpu=$(nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null | head -1 || true)
    printf '{ "bench": "%s", "date": "%s", "host_cores": %s, "load_average": "%s", "gpu": "%s", "commit": "%s", "command": "%s"%s }\n' \
        "$name" "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)" "${gpu:-none}" \
        "${YV_COMMIT:-$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)}" "$command" "$extra"
}
