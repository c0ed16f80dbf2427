#!/usr/bin/env bash
# The shipped arms on aarch64, under emulation: installs the cross linker and qemu-user from
# Debian if they are missing, then builds hya-core and hya-robots for
# aarch64-unknown-linux-gnu and runs their unit and integration tests (the NEON batch against
# single calls, the paired control tick) under qemu; not the doctests. Emulated timings say
# nothing about an aarch64 CPU's speed.
#
#   tools/aarch64_test.sh            # the test profile, as `cargo test`
#   tools/aarch64_test.sh --release
set -euo pipefail
cd "$(dirname "$0")/.."
target=aarch64-unknown-linux-gnu
if ! command -v aarch64-linux-gnu-gcc >/dev/null || ! command -v qemu-aarch64 >/dev/null \
    || [ ! -d /usr/aarch64-linux-gnu/lib ]; then
    command -v apt-get >/dev/null \
        || { echo "needs aarch64-linux-gnu-gcc, its libc and qemu-aarch64: install them" >&2; exit 1; }
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo=sudo
    echo "installing the cross linker and qemu-user (Debian packages)" >&2
    $sudo apt-get update -q
    $sudo apt-get install -y -q gcc-aarch64-linux-gnu libc6-dev-arm64-cross qemu-user
fi
rustup target list --installed | grep -x "$target" >/dev/null || rustup target add "$target"
export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER=aarch64-linux-gnu-gcc
export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER="qemu-aarch64 -L /usr/aarch64-linux-gnu"
cargo test --target "$target" -p hya-core -p hya-robots --tests "$@"
