/* Drives the firmware example of docs/rig/protocol.md (included as fw.c, extracted by
 * tests/protocol_doc_c.rs) through the sequence-gate cases of the protocol's rules. Exit status:
 * 0 if every case behaves as the rules say, otherwise a bit per failed case. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>
static uint64_t T;
static uint64_t now_us(void) { return T; }
static float last_v;
static void dac_write_volts(float v) { last_v = v; }
static int32_t enc0(void) { return 0; }
static int32_t enc1(void) { return 0; }
static void send(const uint8_t *f, int n) { (void)f; (void)n; }
#include "fw.c"
static void cmd(uint32_t s, uint32_t q) {
    uint8_t b[24] = {0};
    b[0] = 'P'; b[1] = 'L'; b[2] = 1; b[3] = 'C';
    put(b + 4, s, 4); put(b + 8, q, 4); put(b + 12, 1000000, 4); put(b + 16, 1, 2);
    put(b + 18, 0, 4); put(b + 22, crc16(b, 22), 2);
    on_command(b, 24);
}
int main(void) {
    int bad = 0;
    cmd(7, 1); cmd(7, 2);
    if (applied_seq != 2) bad |= 1;                 /* in order: accepted */
    cmd(7, 2u + 0x7FFFFFFFu);
    if (applied_seq != 2) bad |= 2;                 /* one wild frame 2^31 - 1 ahead: held */
    cmd(7, 3);
    if (applied_seq != 3) bad |= 4;                 /* the good frame after it: accepted */
    cmd(7, 3);
    if (applied_seq != 3) bad |= 8;                 /* replay: dropped */
    cmd(7, 100000); cmd(7, 100001);
    if (applied_seq != 100001) bad |= 16;           /* a far jump confirmed by the next frame */
    cmd(7, 5);
    if (applied_seq != 100001) bad |= 32;           /* older: dropped */
    cmd(9, 100002);
    if (applied_seq != 100001) bad |= 64;           /* foreign session: dropped */
    printf("firmware gate: %s (%d)\n", bad ? "FAILED" : "ok", bad);
    return bad;
}
