#!/usr/bin/env bash
# Builds the C++ loop with the system's g++ against hya's static library from
# `cargo build --release`: TARGET/release/hya_cpp_loop, TARGET being cargo's target directory
# (`target/`, or CARGO_TARGET_DIR; tools/target_dir.sh prints it).
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -p hya-capi
target="$(tools/target_dir.sh)"
g++ -std=c++17 -O2 -Wall -Wextra -Werror -I hya-capi/include -I examples/cpp \
    examples/cpp/main.cpp examples/cpp/disturbance_rejection_controller.cpp \
    "$target/release/libhya.a" -lpthread -ldl -lm -o "$target/release/hya_cpp_loop"
echo "built $target/release/hya_cpp_loop"
