/*
 * insn_count: a QEMU TCG plugin that counts the guest instructions executed between two
 * marker functions, once per call.
 *
 * Arguments (comma-separated after the plugin path):
 *   begin=ADDR   address of the first instruction of the "begin" marker (hex or decimal; the
 *                Thumb bit of an ELF symbol value is ignored)
 *   end=ADDR     address of the first instruction of the "end" marker
 *   out=PATH     optional: write the results to PATH instead of QEMU's log (qemu_plugin_outs,
 *                shown with `-d plugin`)
 *   profile=PATH optional: also write, per translation block executed inside a region, its
 *                address, instruction count and executions ("tb <addr> <insns> <execs>"), for
 *                a per-function profile (approximate at the region edges: a block is counted
 *                from its start)
 *
 * What is counted: every executed guest instruction adds one to a counter (an inline add, so
 * no callback per instruction). When the begin marker's first instruction executes, the counter
 * is recorded; when the end marker's first instruction executes, the region's count is the
 * difference. So a region counts the instructions executed from the begin marker's entry
 * (inclusive) to the end marker's entry (exclusive): the step between the brackets plus the
 * brackets' own fixed overhead (the begin marker's body and return, the end marker's call),
 * which an empty region measures. One vCPU (mps2-an386 is single core).
 *
 * Output, one line per region, then a summary:
 *   insn_count region <index> <count>
 *   insn_count done regions=<n> unmatched=<m> total=<instructions executed in all>
 *
 * QEMU 7.2 ships no qemu-plugin.h in Debian; the declarations below are those of its plugin
 * API version 1 (include/qemu/qemu-plugin.h of QEMU 7.2), restricted to what is used here.
 * Build: firmware/qemu/build-plugin.sh (gcc -shared -fPIC).
 */
#include <inttypes.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- QEMU plugin API v1 (QEMU 7.2), hand-copied declarations ---- */
#define QEMU_PLUGIN_EXPORT __attribute__((visibility("default")))
typedef uint64_t qemu_plugin_id_t;
typedef struct qemu_info_t {
    const char *target_name;
    struct {
        int min;
        int cur;
    } version;
    bool system_emulation;
    union {
        struct {
            int smp_vcpus;
            int max_vcpus;
        } system;
    };
} qemu_info_t;
struct qemu_plugin_tb;
struct qemu_plugin_insn;
enum qemu_plugin_cb_flags { QEMU_PLUGIN_CB_NO_REGS, QEMU_PLUGIN_CB_R_REGS, QEMU_PLUGIN_CB_RW_REGS };
enum qemu_plugin_op { QEMU_PLUGIN_INLINE_ADD_U64 };
typedef void (*qemu_plugin_udata_cb_t)(qemu_plugin_id_t id, void *userdata);
typedef void (*qemu_plugin_vcpu_udata_cb_t)(unsigned int vcpu_index, void *userdata);
typedef void (*qemu_plugin_vcpu_tb_trans_cb_t)(qemu_plugin_id_t id, struct qemu_plugin_tb *tb);
void qemu_plugin_register_vcpu_tb_trans_cb(qemu_plugin_id_t id, qemu_plugin_vcpu_tb_trans_cb_t cb);
void qemu_plugin_register_vcpu_tb_exec_cb(struct qemu_plugin_tb *tb, qemu_plugin_vcpu_udata_cb_t cb,
                                          enum qemu_plugin_cb_flags flags, void *userdata);
void qemu_plugin_register_vcpu_insn_exec_cb(struct qemu_plugin_insn *insn,
                                            qemu_plugin_vcpu_udata_cb_t cb,
                                            enum qemu_plugin_cb_flags flags, void *userdata);
void qemu_plugin_register_vcpu_insn_exec_inline(struct qemu_plugin_insn *insn,
                                                enum qemu_plugin_op op, void *ptr, uint64_t imm);
size_t qemu_plugin_tb_n_insns(const struct qemu_plugin_tb *tb);
struct qemu_plugin_insn *qemu_plugin_tb_get_insn(const struct qemu_plugin_tb *tb, size_t idx);
uint64_t qemu_plugin_insn_vaddr(const struct qemu_plugin_insn *insn);
void qemu_plugin_register_atexit_cb(qemu_plugin_id_t id, qemu_plugin_udata_cb_t cb, void *userdata);
void qemu_plugin_outs(const char *string);
/* ---- end of the API declarations ---- */

QEMU_PLUGIN_EXPORT int qemu_plugin_version = 1;

static uint64_t begin_addr = UINT64_MAX, end_addr = UINT64_MAX;
static uint64_t executed;       /* instructions executed so far (inline add) */
static uint64_t region_start;   /* `executed` at the last begin marker */
static bool in_region;
static uint64_t *counts;        /* one per completed region */
static size_t n_counts, cap_counts;
static uint64_t unmatched;      /* end without begin, or begin inside a region */
static const char *out_path;
static const char *profile_path;

/* Profile: one slot per translated block (re-translations get their own slot). */
struct tb_slot {
    uint64_t pc;
    uint64_t insns;
    uint64_t execs;
    struct tb_slot *next;
};
static struct tb_slot *slots;

static void on_tb_exec(unsigned int vcpu, void *udata)
{
    (void)vcpu;
    if (in_region) {
        ((struct tb_slot *)udata)->execs++;
    }
}

static void on_begin(unsigned int vcpu, void *udata)
{
    (void)vcpu;
    (void)udata;
    if (in_region) {
        unmatched++;
    }
    in_region = true;
    region_start = executed;
}

static void on_end(unsigned int vcpu, void *udata)
{
    (void)vcpu;
    (void)udata;
    if (!in_region) {
        unmatched++;
        return;
    }
    in_region = false;
    if (n_counts == cap_counts) {
        cap_counts = cap_counts ? 2 * cap_counts : 1024;
        counts = realloc(counts, cap_counts * sizeof *counts);
        if (!counts) {
            abort();
        }
    }
    counts[n_counts++] = executed - region_start;
}

static void on_translate(qemu_plugin_id_t id, struct qemu_plugin_tb *tb)
{
    (void)id;
    size_t n = qemu_plugin_tb_n_insns(tb);
    if (profile_path && n > 0) {
        struct tb_slot *slot = calloc(1, sizeof *slot);
        if (!slot) {
            abort();
        }
        slot->pc = qemu_plugin_insn_vaddr(qemu_plugin_tb_get_insn(tb, 0));
        slot->insns = n;
        slot->next = slots;
        slots = slot;
        qemu_plugin_register_vcpu_tb_exec_cb(tb, on_tb_exec, QEMU_PLUGIN_CB_NO_REGS, slot);
    }
    for (size_t i = 0; i < n; i++) {
        struct qemu_plugin_insn *insn = qemu_plugin_tb_get_insn(tb, i);
        uint64_t pc = qemu_plugin_insn_vaddr(insn);
        /* The marker callbacks are registered before the count, on both markers alike, so
         * the difference is exactly the instructions in [begin entry, end entry). */
        if (pc == begin_addr) {
            qemu_plugin_register_vcpu_insn_exec_cb(insn, on_begin, QEMU_PLUGIN_CB_NO_REGS, NULL);
        } else if (pc == end_addr) {
            qemu_plugin_register_vcpu_insn_exec_cb(insn, on_end, QEMU_PLUGIN_CB_NO_REGS, NULL);
        }
        qemu_plugin_register_vcpu_insn_exec_inline(insn, QEMU_PLUGIN_INLINE_ADD_U64, &executed, 1);
    }
}

static void on_plugin_exit(qemu_plugin_id_t id, void *udata)
{
    (void)id;
    (void)udata;
    FILE *f = out_path ? fopen(out_path, "w") : NULL;
    char line[128];
    for (size_t i = 0; i < n_counts; i++) {
        snprintf(line, sizeof line, "insn_count region %zu %" PRIu64 "\n", i, counts[i]);
        if (f) {
            fputs(line, f);
        } else {
            qemu_plugin_outs(line);
        }
    }
    snprintf(line, sizeof line, "insn_count done regions=%zu unmatched=%" PRIu64 " total=%" PRIu64 "\n",
             n_counts, unmatched + (in_region ? 1 : 0), executed);
    if (f) {
        fputs(line, f);
        fclose(f);
    } else {
        qemu_plugin_outs(line);
    }
    if (profile_path) {
        FILE *p = fopen(profile_path, "w");
        if (p) {
            for (struct tb_slot *t = slots; t; t = t->next) {
                if (t->execs) {
                    fprintf(p, "tb 0x%" PRIx64 " %" PRIu64 " %" PRIu64 "\n", t->pc, t->insns, t->execs);
                }
            }
            fclose(p);
        }
    }
}

static bool parse_addr(const char *s, uint64_t *out)
{
    char *end;
    unsigned long long v = strtoull(s, &end, 0);
    if (*s == '\0' || *end != '\0') {
        return false;
    }
    *out = (uint64_t)v & ~(uint64_t)1; /* Thumb bit of an ELF function symbol */
    return true;
}

QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info,
                                           int argc, char **argv)
{
    (void)info;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        if (strncmp(a, "begin=", 6) == 0 && parse_addr(a + 6, &begin_addr)) {
            continue;
        }
        if (strncmp(a, "end=", 4) == 0 && parse_addr(a + 4, &end_addr)) {
            continue;
        }
        if (strncmp(a, "profile=", 8) == 0 && a[8] != '\0') {
            profile_path = a + 8;
            continue;
        }
        if (strncmp(a, "out=", 4) == 0 && a[4] != '\0') {
            out_path = a + 4;
            continue;
        }
        fprintf(stderr, "insn_count: bad argument '%s' (begin=ADDR,end=ADDR[,out=PATH][,profile=PATH])\n", a);
        return -1;
    }
    if (begin_addr == UINT64_MAX || end_addr == UINT64_MAX || begin_addr == end_addr) {
        fprintf(stderr, "insn_count: need distinct begin=ADDR and end=ADDR\n");
        return -1;
    }
    qemu_plugin_register_vcpu_tb_trans_cb(id, on_translate);
    qemu_plugin_register_atexit_cb(id, on_plugin_exit, NULL);
    return 0;
}
