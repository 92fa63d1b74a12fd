#!/bin/sh
# The book's NMPC swing-up program of Part 2 §3.3 (the C/GMRES code AutoGenU generated,
# `aginvpendC.c` with `rhfuncu.c` and `rhmainu.c`, from the book's support material folder
# `AutoGenU_InvPend`), compiled and run unchanged; its state and input records written as CSV for
# pendulab-book (`crates/book/tests/data/p2c33_aginvpendC04.csv`, read by the example
# `p2c33_adip_nmpc_swing_up` and its test in `crates/book/tests/p2c3.rs`).
#
# The C files themselves are not committed (their licence is not stated); give the folder that
# holds them:
#
#   sh tools/reference/p2c33_book_cgmres.sh <AutoGenU_InvPend folder> > crates/book/tests/data/p2c33_aginvpendC04.csv
#
# As its ReadmeInvPend.txt says, only aginvpendC.c is compiled (it includes the other two). The
# program simulates 0-10 s with ht = 1 ms and saves every dstep = 5th step (t = 0, 5 ms, ...,
# 10 s) into aginvpendC04x.m (x1..x4) and aginvpendC04u.m (u1 = the voltage, u2 = the dummy
# input, u3 = the multiplier), each number as C's "%g" of a float (six significant digits).
# Committed run: gcc (Debian 12.2.0-14+deb12u1) 12.2.0, x86_64, `cc -O2 aginvpendC.c -lm`.
set -eu
src=$(cd "$1" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$src/aginvpendC.c" "$src/rhfuncu.c" "$src/rhmainu.c" "$work/"
cd "$work"
cc -O2 -o aginvpendC aginvpendC.c -lm
./aginvpendC > /dev/null
echo "# the book's aginvpendC.c (Part 2 §3.3), run by tools/reference/p2c33_book_cgmres.sh; $(cc --version | head -n 1)"
echo "t,theta1,theta2,dtheta1,dtheta2,u1,u2,u3"
paste -d ' ' aginvpendC04x.m aginvpendC04u.m |
    awk '{ printf "%.3f,%s,%s,%s,%s,%s,%s,%s\n", (NR - 1) * 0.005, $1, $2, $3, $4, $5, $6, $7 }'
