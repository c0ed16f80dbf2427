#!/usr/bin/env bash
# What `robot!` costs a user at compile time: for each hya commit given (default: HEAD), a
# fresh crate whose only code is `robot!` on Panda's URDF (7 joints) and one call of each
# dynamics function, built clean in debug and release, then rebuilt after touching main.rs (the
# crate alone: the macro's run and compiling what it wrote). Prints wall seconds.
#
#   tools/robot_macro_compile_time.sh b96d1fd HEAD
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'git -C "$repo" worktree prune' EXIT
[ $# -gt 0 ] || set -- HEAD
for commit in "$@"; do
    src="$work/src-$commit"
    git -C "$repo" worktree add --detach "$src" "$commit" >/dev/null 2>&1
    crate="$work/crate-$commit"
    mkdir -p "$crate/src"
    cp "$repo/robots/urdf/panda.urdf" "$crate/"
    cp "$src/Cargo.lock" "$crate/"
    cat > "$crate/Cargo.toml" <<TOML
[package]
name = "compile_time"
version = "0.1.0"
edition = "2021"

[dependencies]
hya-core = { path = "$src/hya-core" }
hya-macros = { path = "$src/hya-macros" }

[workspace]
TOML
    cat > "$crate/src/main.rs" <<'RUST'
use hya_core::{Dynamics, JointVector};

hya_macros::robot!(Panda, "panda.urdf");

fn main() {
    let q = JointVector::<7>::from_element(0.3);
    let d = Panda;
    println!("{}", d.inverse_dynamics(&q, &q, &q));
    println!("{}", d.coriolis_transpose_times_velocity(&q, &q));
    println!("{}", d.gravity(&q));
    println!("{}", d.velocity_terms(&q, &q));
    println!("{}", d.mass_matrix(&q));
    println!("{:?}", d.inverse_dynamics_derivatives(&q, &q, &q));
    println!("{:?}", d.forward_dynamics(&q, &q, &q));
}
RUST
    for profile in debug release; do
        flag=(); [ "$profile" = release ] && flag=(--release)
        rm -rf "$crate/target"
        start=$(date +%s.%N); (cd "$crate" && cargo build -q "${flag[@]}"); clean=$(echo "$(date +%s.%N) - $start" | bc)
        touch "$crate/src/main.rs"
        start=$(date +%s.%N); (cd "$crate" && cargo build -q "${flag[@]}"); alone=$(echo "$(date +%s.%N) - $start" | bc)
        printf '%s %s: clean %.1f s, crate only %.1f s\n' "$commit" "$profile" "$clean" "$alone"
    done
    git -C "$repo" worktree remove --force "$src"
done
rm -rf "$work"
