#!/bin/sh
# The book's M-files that need neither Simulink nor YALMIP, run unchanged in GNU Octave; what
# each displays is written to crates/book/tests/data/octave/<stem>.txt for pendulab-book's test
# crates/book/tests/mfiles_octave.rs (p1c221, p1c321, p1c332). The p1c8 displays are kept for
# reading, not asserted: the two-output observer gain L of p1c83_ex2/p1c84_ex4 is not unique, and
# Octave's place (SLICOT) returns another L than MATLAB's. Nothing here uses pendulab.
#
#   sh tools/reference/book_mfiles_octave.sh <the book's support folder> [output folder]
#
# The support folder holds `mfiles/` and `ip_toolbox/` as published with the book; its M-files
# are not committed here (their licence is not stated). Two shims stand in for MATLAB features the
# runs do not need: `load NAME` of a .mat file reads data/rig/NAME.csv of this repository (the
# same values; `adip_pcont_data_kP_3_ref_1` is data/rig/adip_arm_pcont_data_kP_3_ref_1.csv), and
# the figure commands (figure, plot, set, ...) draw nothing.
#
# cartident.m (called by p1c221_id_cart.m, line 36, on the output of the Simulink model
# cart_model.slx) runs on the model's response written out in closed form, as in
# tools/reference/book_mfiles_p1c2_p1c3.py: the drive z'' = -ac z' + bc v (cdip_para.m: ac = 6.25,
# bc = 4.36) from rest, v = the step ref through the ±5 V saturation and the 16-bit D/A quantizer
# (interval 10/2^16), the position through the encoder quantizer (2*pi/2000 rad of the motor,
# 2000*4.8414e-5 m per turn), sampled at 1 ms from t = 0 to 10 s; then lines 66-77 of the M-file.
#
# The second loop runs the M-files whose displays the book examples compare (crates/book/src/
# chapters/mfile_refs.rs) that call Simulink or need nothing but the control package: unchanged,
# with three more shims: `sim` runs nothing and sets the signals it would log (t, y, u, z, theta,
# ...) to NaN, so the displays before and between the simulations (gains, poles, characteristic
# polynomials) come out and nothing of a simulation does; `input` answers 0 (no animation);
# `format` always keeps `format long g` with long rows unsplit (an M-file's `format short e`
# would print five digits; the examples compare to the digits the M-file's format prints);
# `tzero`, which the control package does not have, is its `zero` (the same transmission zeros).
# p2c13_ex5_adip_lqr_servo and p2c15_ex7_adip_lqr_servo also need mvert.m (mfiles/p2c1).
#
# Committed run: GNU Octave 7.3.0 with its control package 3.4.0 (Debian 12).
set -eu
book=$(cd "$1" && pwd)
repo=$(cd "$(dirname "$0")/../.." && pwd)
out=${2:-$repo/crates/book/tests/data/octave}
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/shim" "$work/noplot" "$work/m"
cat > "$work/shim/load.m" <<'M'
function load(name)
  alias = struct('adip_pcont_data_kP_3_ref_1', 'adip_arm_pcont_data_kP_3_ref_1');
  if isfield(alias, name), name = alias.(name); end
  file = fullfile(getenv('RIG'), [name '.csv']);
  f = fopen(file);
  header = strsplit(strtrim(fgetl(f)), ',');
  fclose(f);
  d = dlmread(file, ',', 1, 0);
  for j = 1:numel(header)
    assignin('caller', header{j}, d(:, j));
  end
end
M
for f in figure plot stairs hold xlim ylim set gca gcf xlabel ylabel legend grid box subplot \
    title axis drawnow close; do
    printf 'function varargout = %s(varargin)\n  varargout = cell(1, nargout);\nend\n' "$f" \
        > "$work/noplot/$f.m"
done
cp "$book"/mfiles/p1c2/cartident.m "$book"/mfiles/p1c3/*.m "$book"/mfiles/p1c8/*.m \
    "$book"/ip_toolbox/iptools/*.m "$work/m/"
cat > "$work/m/p1c221_cartident_run.m" <<'M'
cdip_para
ts = 0.001; t = (0:10000)' * ts;
q_dac = 10/2^16; q_rad = 2*pi/(4*500); m_per_rad = 4*500*4.8414e-5/(2*pi);
refs = [0.8 0.9 1.0 1.1];
for j = 1:4
  v = q_dac*round(min(5, max(-5, refs(j)))/q_dac);
  z = bc*v*(t/ac - (1 - exp(-ac*t))/ac^2);
  y_raw = m_per_rad*(q_rad*round(z/m_per_rad/q_rad));
  [dy, K(j), T(j)] = cartident(t, y_raw, refs(j), 0.001, 1.5);
end
K1 = K(1), K2 = K(2), K3 = K(3), K4 = K(4)
T1 = T(1), T2 = T(2), T3 = T(3), T4 = T(4)
Tave = round( ((T(1)+T(2)+T(3)+T(4))/4)*10^3) / 10^3
Kave = round( ((K(1)+K(2)+K(3)+K(4))/4)*10^3) / 10^3
a = 1/Tave
b = Kave/Tave
M
cd "$work/m"
for stem in p1c221_cartident_run p1c321_cdip_id_cart p1c321_cdip_id_pend p1c332_adip_id_arm \
    p1c332_adip_id_pend p1c83_ex1_zero_order_hold p1c83_ex2_cdip_ob_design_zoh \
    p1c84_ex3_bilinear p1c84_ex4_cdip_ob_design_bilinear; do
    RIG="$repo/data/rig" octave-cli --no-gui --norc --eval \
        "pkg load control; addpath('$work/shim'); addpath('$work/noplot'); warning('off', 'all'); format long g; $stem" \
        2>/dev/null > "$out/$stem.txt" || true
    what="$stem.m run unchanged"
    [ "$stem" = p1c221_cartident_run ] && what="cartident.m run unchanged by this script's driver"
    echo "% $what in $(octave-cli --version | head -n 1), control $(octave-cli --eval "pkg load control; v = pkg('list', 'control'); disp(v{1}.version)" 2>/dev/null)" >> "$out/$stem.txt"
done

# ---------------------------------------------------------------------------------------------
# The second loop (see the header): the M-files with Simulink runs, shimmed.
mkdir "$work/shim2" "$work/m2"
cat > "$work/shim2/sim.m" <<'M'
function sim(varargin)
  for n = {'t', 'y', 'r', 'u', 'v', 'z', 'theta', 'theta1', 'theta2', 'd', 'x', 'xt', 'w', 'e'}
    assignin('caller', n{1}, NaN);
  end
end
M
printf 'function x = input(varargin)\n  x = 0;\nend\n' > "$work/shim2/input.m"
printf 'function format(varargin)\n  builtin("format", "long", "g");\nend\n' > "$work/shim2/format.m"
printf 'function z = tzero(sys)\n  z = zero(sys);\nend\n' > "$work/shim2/tzero.m"
for f in adip_anime cdip_anime; do
    printf 'function %s(varargin)\nend\n' "$f" > "$work/shim2/$f.m"
done
cp "$book"/mfiles/p1c4/*.m "$book"/mfiles/p1c5/*.m "$book"/mfiles/p1c6/*.m "$book"/mfiles/p1c7/*.m \
    "$book"/mfiles/p2c1/mvert.m "$book"/mfiles/p2c1/p2c13_ex5_adip_lqr_servo.m \
    "$book"/mfiles/p2c1/p2c15_ex7_adip_lqr_servo.m "$book"/mfiles/p2c2/p2c244_ex3_cdip_sampled_data_lqr_sim.m \
    "$book"/mfiles/p2c3/*.m \
    "$book"/ip_toolbox/sample_cdip/*.m "$book"/ip_toolbox/sample_adip/*.m "$work/m2/"
for f in "$book"/ip_toolbox/iptools/*_para.m; do cp "$f" "$work/m2/"; done
cd "$work/m2"
for stem in p1c43_stability1 p1c43_stability2 p1c511_ex1 \
    p1c512_ex5 p1c522_ex7_adip_place p1c523_ex8_adip_lqr p1c62_ex1_cart_p_step p1c62_ex2_cart_pi_ramp \
    p1c62_ex3_cart_p_step_dis p1c62_ex4_cart_pi_step_dis p1c63_ex5_cdip_lqr_servo \
    p1c74_ex1_cdip_ob_design p2c13_ex5_adip_lqr_servo p2c15_ex7_adip_lqr_servo \
    p2c244_ex3_cdip_sampled_data_lqr_sim cdip_lqr_sim cdip_lqr_servo_sim adip_lqr_sim \
    adip_lqr_servo_sim p2c323_ex1_cdip_swing_up; do
    octave-cli --no-gui --norc --eval \
        "pkg load control; addpath('$work/shim2'); addpath('$work/noplot'); warning('off', 'all'); split_long_rows(false); builtin('format', 'long', 'g'); $stem" \
        2>/dev/null > "$out/$stem.txt" || true
    echo "% $stem.m run unchanged (sim, input and format shimmed) in $(octave-cli --version | head -n 1), control $(octave-cli --eval "pkg load control; v = pkg('list', 'control'); disp(v{1}.version)" 2>/dev/null)" >> "$out/$stem.txt"
done

# ---------------------------------------------------------------------------------------------
# The numeric part of p1c511_ex4_cdip.m (lines 48 to the end: the book's parameters, ctrb and
# det_Mcn of the 1.2-times pendulum), run unchanged; the lines before it are symbolic (Symbolic
# Math Toolbox), which these runs do not have.
tail -n +48 "$book"/mfiles/p1c5/p1c511_ex4_cdip.m > "$work/m2/p1c511_ex4_cdip_numeric.m"
octave-cli --no-gui --norc --eval \
    "pkg load control; addpath('$work/noplot'); warning('off', 'all'); format long g; p1c511_ex4_cdip_numeric" \
    2>/dev/null > "$out/p1c511_ex4_cdip_numeric.txt" || true
echo "% lines 48 to the end of p1c511_ex4_cdip.m run unchanged in $(octave-cli --version | head -n 1), control $(octave-cli --eval "pkg load control; v = pkg('list', 'control'); disp(v{1}.version)" 2>/dev/null)" >> "$out/p1c511_ex4_cdip_numeric.txt"
