#!/usr/bin/env bash
# Builds the C++ loop with the system's g++ against hya's static library from
# `cargo build --release`: TARGET/release/hya_cpp_loop, TARGET being cargo's target directory
# (`target/`, or CARGO_TARGET_DIR; tools/target_dir.sh prints it).
#
# HYA_CARGO_PROFILE=test links the library `cargo test --workspace` builds instead (TARGET/debug/,
# the test profile, with the features the whole workspace's tests unify, so that neither hya-core
# nor any arm is built again after the tests): CI does, to check the loop without another build of
# the shipped arms.
# Its timings are not the release build's.
set -euo pipefail
cd "$(dirname "$0")/../.."
profile="${HYA_CARGO_PROFILE:-release}"
case "$profile" in
    release) dir=release; cargo build --release -p hya-capi ;;
    # `-p hya-capi` alone would resolve fewer features, and so build hya-core and every arm again.
    test) dir=debug; cargo build --profile test --workspace --lib --tests ;;
    *) echo "HYA_CARGO_PROFILE must be release or test, not \`$profile\`" >&2; exit 2 ;;
esac
target="$(tools/target_dir.sh)/$dir"
g++ -std=c++17 -O2 -Wall -Wextra -Werror -I hya-capi/include -I examples/cpp \
    examples/cpp/main.cpp examples/cpp/disturbance_rejection_controller.cpp \
    "$target/libhya.a" -lpthread -ldl -lm -o "$target/hya_cpp_loop"
echo "built $target/hya_cpp_loop"
