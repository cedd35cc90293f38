#!/usr/bin/env bash
# Modal analysis of the same hex20 mesh, 20 modes, by flexmbs and by CalculiX, in the same run:
# wall time and peak memory (GNU time). Results go to benches/README.md by hand.
# Usage: bash benches/modal_vs_calculix.sh [model.toml]   (needs ccx and /usr/bin/time)
#   default benches/modal_60k.toml (~60 000 DOFs); benches/modal_500k.toml (~500 000 DOFs)
set -euo pipefail
cd "$(dirname "$0")/.."
model="${1:-benches/modal_60k.toml}"
cargo build --release --bin flexmbs >/dev/null
work=$(mktemp -d)
./target/release/flexmbs export-inp "$model" -o "$work/mesh.inp"
cat > "$work/freq.inp" <<DECK
*INCLUDE, INPUT=mesh.inp
*BOUNDARY
XMIN, 1, 3
*STEP
*FREQUENCY
20
*END STEP
DECK
echo "== flexmbs"
/usr/bin/time -f "flexmbs wall %e s, peak RSS %M kB" ./target/release/flexmbs -q modal "$model" > "$work/flexmbs.txt"
head -n 4 "$work/flexmbs.txt"
echo "== CalculiX ($(ccx -v 2>/dev/null | tr -d '\n' | head -c 60))"
(cd "$work" && OMP_NUM_THREADS=2 /usr/bin/time -f "ccx wall %e s, peak RSS %M kB" ccx -i freq > ccx.log)
grep -A 8 "E I G E N V A L U E   O U T P U T" "$work/freq.dat" | tail -n 5
echo "flexmbs frequencies (Hz):"; awk 'NR>2 {print $2}' "$work/flexmbs.txt" | head -n 20 | tr '\n' ' '; echo
echo "ccx frequencies (Hz):"; awk '/E I G E N V A L U E   O U T P U T/{f=1;next} f&&NF==5&&$1~/^[0-9]+$/{print $4}' "$work/freq.dat" | head -n 20 | tr '\n' ' '; echo
rm -rf "$work"
