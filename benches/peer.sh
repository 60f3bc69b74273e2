#!/usr/bin/env bash
# tumbler against LAMMPS on the same bed: the thesis' ch. 4 drum (Chen 2008; D = 0.08 m,
# L = 0.16 m, capped, ~13,500 particles of 2 and 4 mm, linear spring-dashpot t_c = 1e-3 s,
# e = 0.97, Cundall-Strack history, mu = 0.6, dt = 2.5e-5 s, omega = 3.14 rad/s), then
# tumbler alone on Rapaport's run #A.
#
#   benches/peer.sh [REPS]          (default 3)
#
# 1. installs LAMMPS (`apt-get install lammps`) if `lmp` is missing, builds tumbler;
# 2. prepares the reference bed once, in the work directory (PEER_WORK, default
#    target/bench-peer): cases/chen2008-ch4-endwalls.toml, whose tangential force is the
#    Cundall-Strack one (the script makes sure of it: bed-case.toml), poured and
#    turned for 0.5 rotations (1 s) on 2 ranks -> bed.h5, exported with
#    `tumbler export bed.h5 --lammps bed.data`. A bed made from the same bed-case.toml is
#    reused by later invocations; PEER_FRESH=1 makes a new one;
# 3. REPS times, alternating: tumbler 1 rank, LAMMPS 1 rank, tumbler 2 ranks, LAMMPS 2 ranks,
#    each 20,000 steps from that bed, diagnostics at their defaults. LAMMPS reads bed.data
#    into benches/lammps/in.drum with the case's values (2 ranks: `processors 1 1 2`).
#    tumbler starts from bed.h5 with init.kind = "particles", init.file = "bed.h5" and
#    run.rotations set so that exactly 20,000 steps are taken: the same positions,
#    velocities and spins, no contact histories, drum angle 0, as LAMMPS. A tumbler that
#    refuses that file (a build whose explicit particles may overlap by 1 % at most: a
#    settled bed of these soft contacts overlaps by several percent) continues the bed's
#    own run from its checkpoint instead (`--restart bed.ckpt.h5` into a copy of bed.h5,
#    20,000 more steps; the contact histories carried over). PEER_START=file or restart
#    forces one. Every tumbler rank runs under `/usr/bin/time -v` for its peak RSS;
# 4. prints one table (rates, tumbler/LAMMPS ratios, parallel efficiencies, time per phase,
#    tumbler's memory, and a check that both codes ran the same physics: kinetic energy,
#    centre-of-mass angle and spin of the bed at the end, and every 2000 steps from a copy of
#    the tumbler run with snapshots, PEER_SERIES=0 to skip it), then the same tumbler table
#    for cases/rapaport2002-A.toml over 4 rotations, and writes both to WORK/table.md.
#    Logs: WORK/logs/.
#
# Memory: the peak RSS of every rank (`/usr/bin/time -v`, else the last VmHWM read from
# /proc every 0.2 s). Per particle: the ranks' peak RSS summed, divided by the particles.
# Excluding the ~fixed baseline of a process (MPI, HDF5, the diagnostics' window sums): small
# runs of the same case and length on 1 and 2 ranks (ch. 4: a quarter of the bed's particles
# along the curved wall; #A: its lattice at 1/20 of the density) give the baseline on the
# same number of ranks, and (sum of peak RSS - sum of the small run's peak RSS) /
# (particles - small run's particles) is what a particle costs. (Rank 0 holds the
# reductions and gathers, so on 2 ranks its baseline is higher than the other rank's; both
# ranks' values are shown.)
# `tumbler check`'s estimate of the same is shown beside, as benches/memory.sh does: its
# memory over the ranks for the run less its memory over the ranks for the small run, divided
# by the same difference of particles (so a transient that both runs share, such as the
# window sums' write, cancels in both), and the ratio estimate / measured.
#
# Other settings: PEER_WORK (work directory), PEER_FRESH=1 (new bed), PEER_START
# (auto|file|restart), PEER_SERIES=0, PEER_STEPS and PEER_ROTATIONS_A (shorter runs, to try
# the script out).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
reps="${1:-3}"
[[ "$reps" =~ ^[1-9][0-9]*$ ]] || { echo "usage: benches/peer.sh [REPS]" >&2; exit 2; }
work="${PEER_WORK:-$here/target/bench-peer}"
case_src="$here/cases/chen2008-ch4-endwalls.toml"
case_a="$here/cases/rapaport2002-A.toml"
deck="$here/benches/lammps/in.drum"
steps="${PEER_STEPS:-20000}"            # timed steps per run (20,000 for the table)
rotations_a="${PEER_ROTATIONS_A:-4}"  # run #A length, rotations
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
mpirun=(mpirun --oversubscribe)

say() { printf '== %s\n' "$*"; }
fail() { printf 'error: %s\n' "$*" >&2; exit 1; }
# run a command with its output in a log; on failure show the log's end and stop (or, with
# soft=1 in the environment, warn and return 1)
logged() {
  local log="$1" cmd; shift
  "$@" >"$log" 2>&1 && return 0
  cmd="$*"
  [ "${#cmd}" -gt 300 ] && cmd="${cmd:0:300}..."
  grep -v '^	' "$log" | tail -n 12 >&2
  [ "${soft:-0}" = 1 ] && { printf 'warning: failed (log: %s): %s\n' "$log" "$cmd" >&2; return 1; }
  fail "failed (log: $log): $cmd"
}

# ---- 1. LAMMPS, python3 (reads the case), tumbler ----
if ! command -v lmp >/dev/null 2>&1; then
  say "installing LAMMPS (Debian package lammps)"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq lammps >/dev/null
fi
command -v lmp >/dev/null 2>&1 || fail "lmp not found after installing lammps"
command -v mpirun >/dev/null 2>&1 || fail "mpirun not found (scripts/setup.sh installs OpenMPI)"
command -v python3 >/dev/null 2>&1 || fail "python3 (3.11+, for tomllib) is needed to read the case"
say "building tumbler"
cargo build --release --manifest-path "$here/Cargo.toml"
bin="$here/target/release/tumbler"

mkdir -p "$work/logs"
cd "$work"
logs="$work/logs"
# the logs of an earlier invocation go (but the bed's, which may be reused)
find "$logs" -maxdepth 1 -type f ! -name bed.log ! -name export-bed.log -delete
say "work directory $work (logs in $logs)"

# peak RSS per process: /usr/bin/time -v, else a /proc poller (same output line)
if [ -x /usr/bin/time ]; then
  rss=(/usr/bin/time -v)
  rss_how="/usr/bin/time -v, its Maximum resident set size"
else
  cat >"$work/peak-rss.sh" <<'EOF'
#!/usr/bin/env bash
# run "$@", reading its VmHWM from /proc every 0.2 s; print it as /usr/bin/time -v does
"$@" &
pid=$!
peak=0
while kill -0 "$pid" 2>/dev/null; do
  v=$(awk '/^VmHWM/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
  [ -n "$v" ] && peak=$v
  sleep 0.2
done
wait "$pid" && rc=0 || rc=$?
echo "	Maximum resident set size (kbytes): $peak" >&2
exit "$rc"
EOF
  chmod +x "$work/peak-rss.sh"
  rss=("$work/peak-rss.sh")
  rss_how="VmHWM polled from /proc every 0.2 s (may miss a last peak)"
fi

# ---- 2. the reference bed ----
# the ch. 4 case with the Cundall-Strack history force (the LAMMPS deck's linear_history);
# the case uses it already, the edit guards against a case switched back to "viscous"
sed -e '/^gamma_s *=/d' -e 's/^tangential *= *"viscous"/tangential = "history"/' \
  "$case_src" >bed-case.toml.new
grep -q '^tangential = "history"' bed-case.toml.new || fail "could not switch $case_src to the history force"
mv bed-case.toml.new bed-case.toml
logged "$logs/check-bed.log" "$bin" check bed-case.toml --ranks 2

stamp="$(sha256sum bed-case.toml | cut -c1-16) 0.5 rotations 2 ranks"
if [ "${PEER_FRESH:-0}" != 1 ] && [ -s bed.h5 ] && [ -s bed.ckpt.h5 ] && [ -s bed.data ] \
  && [ "$(cat bed.stamp 2>/dev/null)" = "$stamp" ]; then
  say "reusing the bed in $work/bed.h5 (PEER_FRESH=1 makes a new one)"
else
  say "preparing the bed: pour + 0.5 rotations on 2 ranks (several minutes; log $logs/bed.log)"
  rm -f bed.stamp
  logged "$logs/bed.log" "${mpirun[@]}" -np 2 "$bin" run bed-case.toml --set run.rotations=0.5 \
    -o bed.h5 --overwrite
  logged "$logs/export-bed.log" "$bin" export bed.h5 --lammps bed.data
  echo "$stamp" >bed.stamp
fi
cat "$logs/export-bed.log" 2>/dev/null || true
bed_steps=$("$bin" info bed.h5 | sed -n 's/^steps: *\([0-9]*\)$/\1/p')
[ -n "$bed_steps" ] || fail "bed.h5 has no steps attribute"

# ---- the case's values: LAMMPS variables, 20,000 steps in rotations, small runs ----
values=$(python3 - bed-case.toml "$steps" "$bed_steps" <<'EOF'
import math, sys, tomllib
c = tomllib.load(open(sys.argv[1], "rb"))
steps, bed_steps = int(sys.argv[2]), int(sys.argv[3])
d, m, sp, run = c["drum"], c["model"], c["species"], c.get("run", {})
why = []
if d.get("shape", "cylinder") != "cylinder": why.append("drum.shape must be cylinder")
if m.get("family") != "spring-dashpot" or m.get("normal", "linear") != "linear": why.append("linear spring-dashpot only")
if m.get("tangential") != "history": why.append("model.tangential must be history")
if len(sp) != 2: why.append("exactly two species")
if d.get("rough_wall") or d.get("cap_low", "frictional") != "frictional" or d.get("cap_high", "frictional") != "frictional":
    why.append("smooth frictional walls only")
if why:
    sys.exit("the LAMMPS deck does not cover this case: " + "; ".join(why))
tc, omega = m["collision_time"], d["omega"]
dt = run.get("dt", tc / 40.0)
mu = [s["mu"] for s in sp]
muw = [s.get("mu_wall", s["mu"]) for s in sp]
if any(s.get("mu_cap", w) != w for s, w in zip(sp, muw)):
    sys.exit("the LAMMPS deck's drum region has one friction for the wall and the caps")
v = dict(D=d["diameter"], L=d["length"], omega=omega, g=m["gravity"],
         rho=m.get("density", 6 / math.pi), tc=tc, e=m["restitution"],
         ktf=m.get("stiffness_ratio", 2 / 7), dt=dt, d1=sp[0]["diameter"], d2=sp[1]["diameter"],
         mu1=mu[0], mu2=mu[1], muw1=muw[0], muw2=muw[1])
bz = "p" if d.get("ends") == "periodic" else "f"
print("lmpvars=(" + " ".join(f"-var {k} {x!r}" for k, x in v.items()) + f" -var bz {bz})")
print(f"rho={v['rho']!r}")
print(f"rot_steps={steps * omega * dt / (2 * math.pi):.15g}")
print(f"rot_total={(bed_steps + steps) * omega * dt / (2 * math.pi):.15g}")
print(f"snap_every={2000 * omega * dt / (2 * math.pi):.15g}")
EOF
) || fail "cannot take the LAMMPS deck's values from bed-case.toml"
eval "$values"
# The small runs for the memory baseline. ch. 4: small-case.toml, bed-case.toml with a
# quarter of the bed's particles next to the curved wall (every 4th of those whose centre is
# within 0.7 d of it) as [[init.particle]] tables, at rest, without those that touch each
# other or overlap a wall by more than 0.5 % (any tumbler accepts them; lying on the wall,
# they do not fall onto each other); run #A: its lattice at 1/20 of the density.
python3 - bed.data bed-case.toml small-case.toml <<'EOF' || fail "cannot write small-case.toml from bed.data"
import math, re, sys, tomllib
text = open(sys.argv[2]).read()
c = tomllib.loads(text)
R, H = 0.5 * c["drum"]["diameter"], 0.5 * c["drum"]["length"]
atoms, sec = [], None
for line in open(sys.argv[1]):
    w = line.split()
    if line.startswith("Atoms"): sec = "a"; continue
    if line.startswith("Velocities"): break
    if sec == "a" and len(w) == 7:
        atoms.append((int(w[0]), int(w[1]) - 1, float(w[2]), float(w[4]), float(w[5]), float(w[6])))
atoms.sort()
wall = [a for a in atoms if R - math.hypot(a[3], a[4]) < 0.7 * a[2]]
keep = []
for a in wall[::4]:
    _, s, d, x, y, z = a
    if math.hypot(x, y) + 0.495 * d > R or abs(z) + 0.495 * d > H:
        continue
    if any(math.dist((x, y, z), b[3:]) < 0.5 * (d + b[2]) for b in keep):
        continue
    keep.append(a)
text = re.sub(r'(?m)^kind *= *"pour" *$', 'kind = "particles"', text)
text = re.sub(r'(?m)^(fill|grow_time|settle_time) *=.*$\n?', '', text)
text += "\n# the small run of benches/peer.sh: particles of bed.data next to the curved wall, at rest\n"
for _, s, d, x, y, z in keep:
    text += ("\n[[init.particle]]\nspecies = %d\ndiameter = %r\nposition = [%r, %r, %r]\n"
             "velocity = [0.0, 0.0, 0.0]\nangular_velocity = [0.0, 0.0, 0.0]\n" % (s, d, x, y, z))
open(sys.argv[3], "w").write(text)
EOF
density_a=$(python3 -c 'import sys, tomllib; print(repr(tomllib.load(open(sys.argv[1], "rb"))["init"]["density"] / 20))' "$case_a") \
  || fail "cannot read init.density from $case_a"

start="${PEER_START:-auto}"
if [ "$start" = auto ]; then
  if "$bin" check bed-case.toml --set 'init.kind="particles"' --set 'init.file="bed.h5"' \
    >"$logs/check-file.log" 2>&1; then
    start=file
  else
    start=restart
    say "tumbler refuses bed.h5 as init.file ($(grep -m1 'error\|init' "$logs/check-file.log")): continuing the bed's checkpoint instead"
  fi
fi
case "$start" in
  restart)
    timed=(--restart bed.ckpt.h5 --set "run.rotations=$rot_total")
    checked=(--set "run.rotations=$rot_total")
    want=$((bed_steps + steps)) ;;
  file)
    timed=(--set 'init.kind="particles"' --set 'init.file="bed.h5"' --set "run.rotations=$rot_steps")
    checked=("${timed[@]}")
    want=$steps ;;
  *) fail "PEER_START must be auto, file or restart" ;;
esac
"$bin" check bed-case.toml "${checked[@]}" --ranks 2 >"$logs/check-timed.log" 2>&1 \
  || { cat "$logs/check-timed.log" >&2; fail "the timed case was refused"; }
grep -q "= $want steps" "$logs/check-timed.log" \
  || fail "the run.rotations given does not make $want steps: $(grep '^run' "$logs/check-timed.log")"
if [ "$start" = restart ]; then
  say "timed runs: tumbler continues bed.ckpt.h5 from step $bed_steps to $want, LAMMPS runs $steps steps from bed.data"
else
  say "timed runs: $steps steps = $rot_steps rotations, from bed.h5 / bed.data"
fi

# ---- parsing ----
tumbler_rate() { sed -n 's/.*done: .* \([0-9.]*\) M particle-steps\/s on.*/\1/p' "$1"; }
tumbler_particles() { sed -n 's/.*: \([0-9]*\) particles on [0-9]* ranks, .*/\1/p' "$1" | head -n1; }
# "name|seconds" per phase, from the table after "done:"
tumbler_phases() {
  sed -n '/done: /,$p' "$1" | sed -n 's/^\(\[[^]]*\]\)\{0,1\} \{2,\}\(.*[^ ]\) \{1,\}\([0-9.]\{1,\}\) s \{1,\}[0-9.]\{1,\}%$/\2|\3/p'
}
# peak RSS of every rank (kB), one line each
peak_rss() { sed -n 's/.*Maximum resident set size (kbytes): \([0-9]*\).*/\1/p' "$1"; }
lammps_rate() { awk '/^Loop time of/ { printf "%.4f\n", $12 * $9 / $4 / 1e6 }' "$1" | tail -n1; }
lammps_section() { awk -F'|' -v s="$2" '{ n = $1; gsub(/ /, "", n) } n == s && NF >= 6 { gsub(/ /, "", $3); print $3 }' "$1" | tail -n1; }
median() { sed '/^$/d' | sort -g | awk '{a[NR]=$1} END {if (NR==0) print "-"; else print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
median_of() { echo "${1:-}" | tr ' ' '\n' | median; }
list() { tr ' ' '\n' | sed '/^$/d' | paste -sd' ' - | sed 's/ /, /g'; }

# ---- 3. the runs ----
declare -A rate_t rate_l phase rss_sum rss_max rss_ranks count
phase_names=""
run_tumbler() {  # tag np log args...
  local tag="$1" np="$2" log="$3"; shift 3
  logged "$log" "${mpirun[@]}" -np "$np" "${rss[@]}" "$bin" run "$@" --overwrite || return 1
  local r; r=$(tumbler_rate "$log")
  [ -n "$r" ] || fail "no 'done:' line in $log"
  rate_t[$tag.$np]="${rate_t[$tag.$np]:-} $r"
  count[$tag]=$(tumbler_particles "$log")
  rss_sum[$tag.$np]="${rss_sum[$tag.$np]:-} $(peak_rss "$log" | awk '{s += $1} END {print s + 0}')"
  rss_max[$tag.$np]="${rss_max[$tag.$np]:-} $(peak_rss "$log" | awk '$1 > m {m = $1} END {print m + 0}')"
  rss_ranks[$tag.$np]=$(peak_rss "$log" | sort -g | awk '{printf "%s%.1f", (NR > 1 ? ", " : ""), $1 / 1024}')
  local name secs
  while IFS='|' read -r name secs; do
    phase[$tag.$np.$name]="${phase[$tag.$np.$name]:-} $secs"
    case "$phase_names" in *"|$name|"*) ;; *) phase_names="$phase_names|$name|" ;; esac
  done < <(tumbler_phases "$log")
  echo "   tumbler $np rank(s): $r M particle-steps/s (log $log)"
}
run_lammps() {  # np rep
  local np="$1" k="$2" log="$logs/lammps-np$1.r$2.log"
  logged "$logs/lammps-np$np.r$k.out" "${mpirun[@]}" -np "$np" lmp -in "$deck" -var data bed.data \
    -var pz "$np" -var nrun "$steps" -var dumpfile "lammps-np$np.r$k.dump" "${lmpvars[@]}" \
    -log "$log" -screen none
  local r; r=$(lammps_rate "$log")
  [ -n "$r" ] || fail "no 'Loop time' line in $log"
  rate_l[$np]="${rate_l[$np]:-} $r"
  local s
  for s in Pair Neigh Comm Modify Other; do
    phase[lammps.$np.$s]="${phase[lammps.$np.$s]:-} $(lammps_section "$log" "$s")"
  done
  echo "   LAMMPS  $np rank(s): $r M particle-steps/s (log $log)"
}

say "machine: $(nproc --all) cores, load $(cut -d' ' -f1-3 /proc/loadavg); LAMMPS $(lmp -h | sed -n 's/^Large-scale Atomic\/Molecular Massively Parallel Simulator - //p' | head -n1)"
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
for k in $(seq "$reps"); do
  for np in 1 2; do
    say "repetition $k/$reps, $np rank(s)"
    if [ "$start" = restart ]; then cp bed.h5 "tumbler-np$np.r$k.h5"; fi  # the restart appends to it
    run_tumbler ch4 "$np" "$logs/tumbler-np$np.r$k.log" bed-case.toml "${timed[@]}" -o "tumbler-np$np.r$k.h5"
    run_lammps "$np" "$k"
  done
done
load_end=$(cut -d' ' -f1-3 /proc/loadavg)
say "memory baseline: small runs of the same case and length (small-case.toml)"
for np in 1 2; do
  soft=1 run_tumbler ch4small "$np" "$logs/tumbler-small-np$np.log" small-case.toml \
    --set "run.rotations=$rot_steps" --set run.max_overlap=0.5 -o "small-np$np.h5" || true
done
series=""
if [ "$start" = file ] && [ "${PEER_SERIES:-1}" = 1 ]; then
  say "the same tumbler run with a snapshot every 2000 steps (not timed), for the comparison"
  logged "$logs/tumbler-series.log" "${mpirun[@]}" -np 2 "$bin" run bed-case.toml "${timed[@]}" \
    --set "diagnostics.snapshots.every=$snap_every" -o series.h5 --overwrite
  series=series.h5
fi

say "Rapaport #A, $rotations_a rotations, tumbler alone"
for k in $(seq "$reps"); do
  for np in 1 2; do
    run_tumbler A "$np" "$logs/A-np$np.r$k.log" "$case_a" --set "run.rotations=$rotations_a" -o "A-np$np.r$k.h5"
  done
done
for np in 1 2; do
  soft=1 run_tumbler Asmall "$np" "$logs/A-small-np$np.log" "$case_a" --set "run.rotations=$rotations_a" \
    --set "init.density=$density_a" --set run.max_overlap=0.5 -o "A-small-np$np.h5" || true
done

# ---- 4. the tables ----
# a bed's state from a LAMMPS data file (tumbler export) or dump (id type diameter x y z vx vy
# vz): particles|translational KE (J)|centre-of-mass angle from the downward vertical (deg,
# towards +x)|mean particle omega_z about the axis (LAMMPS' c_wzav)|Lz/Iz of the bed (rad/s)
stats() {
  awk -v rho="$rho" '
    function add(x, y, vx, vy, vz, d,   m, r2, l) {
      m = rho * 3.141592653589793 / 6 * d * d * d; r2 = x * x + y * y; l = x * vy - y * vx
      M += m; X += m * x; Y += m * y; K += 0.5 * m * (vx * vx + vy * vy + vz * vz)
      W += l / r2; Lz += m * l; Iz += m * r2; N++
    }
    /^Atoms/ { sec = "a"; next } /^Velocities/ { sec = "v"; next }
    /^ITEM: ATOMS/ { sec = "d"; for (i = 3; i <= NF; i++) col[$i] = i - 2; next }
    /^ITEM:/ { sec = ""; next }
    NF == 0 { next }
    sec == "a" && NF >= 7 { d[$1] = $3; x[$1] = $5; y[$1] = $6 }
    sec == "v" && NF >= 7 { vx[$1] = $2; vy[$1] = $3; vz[$1] = $4 }
    sec == "d" { add($col["x"], $col["y"], $col["vx"], $col["vy"], $col["vz"], $col["diameter"]) }
    END {
      for (i in vx) add(x[i], y[i], vx[i], vy[i], vz[i], d[i])
      printf "%d|%.4g|%.2f|%.3f|%.3f\n", N, K, atan2(X / M, -Y / M) * 180 / 3.141592653589793, W / N, Lz / Iz
    }' "$1"
}
lammps_thermo() {  # log step -> "ke|comang|wzav"
  awk -v s="$2" '/^ *Step / { on = 1; next } /^Loop time/ { on = 0 }
    on && $1 == s { printf "%.4g|%.2f|%.3f\n", $3, $5, $4 }' "$1" | tail -n1
}
eff() { awk -v a="$1" -v b="$2" 'BEGIN { if (a > 0) printf "%.0f %%", 100 * b / (2 * a); else print "-" }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b > 0) printf "%.2f", a / b; else print "-" }'; }
per_rank() { awk -v r="$1" -v n="$2" 'BEGIN { printf "%.3f", r / n }'; }
phase_rows() {  # tag: median seconds per phase, 1 and 2 ranks
  local name names
  IFS='|' read -ra names <<<"$phase_names"
  for name in "${names[@]}"; do
    [ -n "$name" ] || continue
    echo "| $name | $(median_of "${phase[$1.1.$name]:-}") | $(median_of "${phase[$1.2.$name]:-}") |"
  done
}
check_mib() {  # ranks check-args...: `tumbler check`'s memory over the ranks, MiB
  local np="$1"; shift
  "$bin" check "$@" --ranks "$np" 2>/dev/null | sed -n 's/.* \([0-9.]*\) MiB over the ranks.*/\1/p'
}
memory_rows() {  # tag small-tag; the check arguments of the two runs in big_check, small_check
  local tag="$1" small="$2" np
  for np in 1 2; do
    awk -v np="$np" -v s="$(median_of "${rss_sum[$tag.$np]:-}")" -v mx="$(median_of "${rss_max[$tag.$np]:-}")" \
      -v ranks="${rss_ranks[$tag.$np]:-}" -v n="${count[$tag]}" -v base="$(median_of "${rss_sum[$small.$np]:-}")" \
      -v n_small="${count[$small]:-0}" -v branks="${rss_ranks[$small.$np]:-}" \
      -v e="$(check_mib "$np" "${big_check[@]}")" -v e0="$(check_mib "$np" "${small_check[@]}")" 'BEGIN {
        ok = base != "-" && n > n_small
        excl = 0; est = 0; m = "-"; x = "-"; q = "-"
        if (ok) { excl = (s - base) * 1024 / (n - n_small); m = sprintf("%.0f", excl) }
        if (ok && e != "" && e0 != "") { est = (e - e0) * 1048576 / (n - n_small); x = sprintf("%.0f", est) }
        if (est > 0 && excl > 0) q = sprintf("%.2f", est / excl)
        printf("| %d | %.1f (%s) | %.0f | %s | %s | %s | %s |\n", np, mx / 1024, ranks, s * 1024 / n, branks, m, x, q) }'
  done
}
memory_header() {  # small-tag
  echo "| ranks | peak RSS per rank, MiB: largest (all) | B/particle: sum of peak RSS / particles | small run (${count[$1]:-?} particles): peak RSS per rank, MiB | B/particle excl. baseline: (sum of peak RSS - the small run's sum on as many ranks) / (particles - the small run's) | \`tumbler check\` estimate, B/particle: (its MiB over the ranks - the small run's) / (particles - the small run's) | estimate / measured |"
  echo "|---|---|---|---|---|---|---|"
}

table="$work/table.md"
{
  t1=$(median_of "${rate_t[ch4.1]}"); t2=$(median_of "${rate_t[ch4.2]}")
  l1=$(median_of "${rate_l[1]}"); l2=$(median_of "${rate_l[2]}")
  if [ "$start" = restart ]; then
    how="tumbler continues the bed's run from bed.ckpt.h5 (contact histories kept), LAMMPS reads bed.data"
  else
    how="tumbler reads bed.h5 (init.file), LAMMPS bed.data: same positions, velocities and spins, no contact histories"
  fi
  echo "## tumbler vs LAMMPS: thesis ch. 4 drum, same bed, $steps steps"
  echo
  echo "${count[ch4]} particles. Bed: bed-case.toml (cases/chen2008-ch4-endwalls.toml with the history"
  echo "tangential force) poured and turned 0.5 rotations on 2 ranks; $how."
  echo "$reps alternating repetitions; $(nproc --all) cores, load average $load_start at the start of the timed runs,"
  echo "$load_end at their end; $(date -u '+%Y-%m-%d %H:%M UTC'); tumbler $(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo '?')$(git -C "$here" diff --quiet 2>/dev/null || echo ' with uncommitted changes');"
  echo "LAMMPS $(lmp -h | sed -n 's/^Large-scale Atomic\/Molecular Massively Parallel Simulator - //p' | head -n1). M particle-steps/s = particles x steps / time of the step loop"
  echo "(tumbler: its \`done:\` line, diagnostics at their defaults; LAMMPS: its \`Loop time\`)."
  echo
  echo "| code | ranks | M particle-steps/s (median) | all runs | per rank |"
  echo "|---|---|---|---|---|"
  for np in 1 2; do
    t=$(median_of "${rate_t[ch4.$np]}"); l=$(median_of "${rate_l[$np]}")
    echo "| tumbler | $np | $t | $(echo "${rate_t[ch4.$np]}" | list) | $(per_rank "$t" "$np") |"
    echo "| LAMMPS | $np | $l | $(echo "${rate_l[$np]}" | list) | $(per_rank "$l" "$np") |"
  done
  echo
  echo "| | 1 rank | 2 ranks |"
  echo "|---|---|---|"
  echo "| tumbler / LAMMPS | $(ratio "$t1" "$l1") | $(ratio "$t2" "$l2") |"
  echo "| parallel efficiency (2-rank rate / (2 x 1-rank rate)), tumbler | | $(eff "$t1" "$t2") |"
  echo "| parallel efficiency, LAMMPS | | $(eff "$l1" "$l2") |"
  echo
  echo "| tumbler phase (rank 0), s (median) | 1 rank | 2 ranks |"
  echo "|---|---|---|"
  phase_rows ch4
  echo
  echo "| LAMMPS section (average over ranks), s (median) | 1 rank | 2 ranks |"
  echo "|---|---|---|"
  for s in Pair Neigh Comm Modify Other; do
    echo "| $s | $(median_of "${phase[lammps.1.$s]:-}") | $(median_of "${phase[lammps.2.$s]:-}") |"
  done
  echo
  echo "tumbler's memory: peak RSS of each rank ($rss_how), median over the repetitions."
  echo "Baseline: the ~fixed cost of a process (MPI, HDF5, the diagnostics' window sums), the smallest"
  echo "peak RSS of any rank of two small runs of the same case and length on 1 and 2 ranks (${count[ch4small]:-?} particles"
  echo "of the bed, next to the wall); what is left per particle is its storage, ghosts, pair list and gathers."
  echo
  memory_header ch4small
  big_check=(bed-case.toml "${checked[@]}")
  small_check=(small-case.toml --set "run.rotations=$rot_steps" --set run.max_overlap=0.5)
  memory_rows ch4 ch4small
  echo
  echo "### Same physics?"
  echo
  echo "Translational kinetic energy, the bed's centre-of-mass angle from the downward vertical, the"
  echo "particles' mean omega_z about the axis and the bed's Lz/Iz, at the start and after $steps steps"
  echo "(repetition $reps). Similar, not identical, values are expected: the two codes' k_n differ"
  echo "for particles off their species' nominal size, and the flow is chaotic."
  echo
  echo "| | step | particles | KE (J) | COM angle (deg) | mean omega_z (rad/s) | Lz/Iz (rad/s) |"
  echo "|---|---|---|---|---|---|---|"
  echo "| bed.data | 0 | $(stats bed.data | sed 's/|/ | /g') |"
  IFS='|' read -r ke ang wz <<<"$(lammps_thermo "$logs/lammps-np1.r$reps.log" 0)"
  echo "| LAMMPS thermo | 0 | | $ke | $ang | $wz | |"
  for np in 1 2; do
    IFS='|' read -r ke ang wz <<<"$(lammps_thermo "$logs/lammps-np$np.r$reps.log" "$steps")"
    echo "| LAMMPS $np rank(s), thermo | $steps | | $ke | $ang | $wz | |"
    echo "| LAMMPS $np rank(s), final dump | $steps | $(stats "lammps-np$np.r$reps.dump" | sed 's/|/ | /g') |"
    "$bin" export "tumbler-np$np.r$reps.h5" --lammps "tumbler-np$np.r$reps.data" >/dev/null
    echo "| tumbler $np rank(s), /particles | $want | $(stats "tumbler-np$np.r$reps.data" | sed 's/|/ | /g') |"
  done
  if [ -n "$series" ]; then
    echo
    echo "Through the run: LAMMPS' thermo lines (1 and 2 ranks) against tumbler's snapshots (a run"
    echo "identical to the timed ones, the same bits on any rank count, with a snapshot every 2000 steps):"
    echo
    echo "| step | KE (J) LAMMPS 1 / 2 ranks | KE tumbler | COM angle LAMMPS 1 / 2 | COM angle tumbler | mean omega_z LAMMPS 1 / 2 | mean omega_z tumbler |"
    echo "|---|---|---|---|---|---|---|"
    for s in $(seq 0 2000 "$steps"); do
      IFS='|' read -r k1 a1 w1 <<<"$(lammps_thermo "$logs/lammps-np1.r$reps.log" "$s")"
      IFS='|' read -r k2 a2 w2 <<<"$(lammps_thermo "$logs/lammps-np2.r$reps.log" "$s")"
      if "$bin" export "$series" --lammps snapshot.data --group "$(printf 'snapshots/%010d' "$s")" >/dev/null 2>&1; then
        IFS='|' read -r _ kt at wt _ <<<"$(stats snapshot.data)"
      else
        kt="-"; at="-"; wt="-"
      fi
      echo "| $s | $k1 / $k2 | $kt | $a1 / $a2 | $at | $w1 / $w2 | $wt |"
    done
    rm -f snapshot.data
  fi
  echo
  a1=$(median_of "${rate_t[A.1]}"); a2=$(median_of "${rate_t[A.2]}")
  echo "## tumbler alone: Rapaport #A, $rotations_a rotations"
  echo
  echo "${count[A]} particles, $reps alternating repetitions, diagnostics at their defaults."
  echo
  echo "| ranks | M particle-steps/s (median) | all runs | per rank | parallel efficiency |"
  echo "|---|---|---|---|---|"
  echo "| 1 | $a1 | $(echo "${rate_t[A.1]}" | list) | $a1 | |"
  echo "| 2 | $a2 | $(echo "${rate_t[A.2]}" | list) | $(per_rank "$a2" 2) | $(eff "$a1" "$a2") |"
  echo
  echo "| tumbler phase (rank 0), s (median) | 1 rank | 2 ranks |"
  echo "|---|---|---|"
  phase_rows A
  echo
  echo "Memory as above; the small runs are the case's lattice at 1/20 of its density (${count[Asmall]:-?} particles)."
  echo
  memory_header Asmall
  big_check=("$case_a" --set "run.rotations=$rotations_a")
  small_check=("$case_a" --set "run.rotations=$rotations_a" --set "init.density=$density_a" --set run.max_overlap=0.5)
  memory_rows A Asmall
} >"$table"
echo
cat "$table"
echo
say "table written to $table; logs in $logs; bed in $work/bed.h5 and $work/bed.data"
