/* The option table (cli/options.c) is the one place the options are
 * written down: the committed bash completion and the man page's SYNOPSIS
 * are what edgewise_gen writes from it (run `make cli_docs` after changing
 * the table), each command's --help lists every option the table gives it,
 * the completion offers every --hsr method, and the unknown-command
 * message names every command. */
#define _POSIX_C_SOURCE 200809L  /* mkdtemp */
#include "util.h"
#include "options.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

/* options.c reports through it (its parser is not run here). */
void error_line(const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

static char *slurp(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (buf) buf[fread(buf, 1, (size_t)n, f)] = '\0';
    fclose(f);
    return buf;
}

/* Runs the generator with args; its exit status. */
static int run_gen(const char *gen, const char *a1, const char *a2, const char *a3) {
    pid_t pid = fork();
    if (pid == 0) {
        execl(gen, gen, a1, a2, a3, (char *)NULL);
        _exit(127);
    }
    int st = 0;
    if (pid < 0 || waitpid(pid, &st, 0) < 0) return -1;
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* The committed file and the generator's are the same text. */
static void same_file(const char *committed, const char *generated, const char *what) {
    char *a = slurp(committed), *b = slurp(generated);
    CHECK(a && b, "%s: cannot read %s or %s", what, committed, generated);
    if (a && b) {
        size_t i = 0;
        while (a[i] && a[i] == b[i]) i++;
        int line = 1;
        for (size_t k = 0; k < i; k++) line += a[k] == '\n';
        CHECK(a[i] == b[i], "%s: %s differs from the option table's at line %d (run `make cli_docs`)", what,
              committed, line);
    }
    free(a), free(b);
}

int main(void) {
    const char *gen = getenv("EW_GEN"), *src = getenv("EW_SOURCE");
    if (!gen || !src || !getenv("EW_CLI")) {
        fprintf(stderr, "EW_GEN, EW_SOURCE or EW_CLI not set (run through ctest): skipped\n");
        return 77;
    }
    char tmp[] = "/tmp/ew_cli_table_XXXXXX";
    if (!mkdtemp(tmp)) {
        CHECK(0, "mkdtemp");
        return ew_t_finish();
    }
    char comp[128], man[128], committed_comp[1024], committed_man[1024];
    snprintf(comp, sizeof comp, "%s/edgewise.bash", tmp);
    snprintf(man, sizeof man, "%s/edgewise.1", tmp);
    snprintf(committed_comp, sizeof committed_comp, "%s/completion/edgewise.bash", src);
    snprintf(committed_man, sizeof committed_man, "%s/docs/edgewise.1", src);

    /* 1. the generated files are the committed ones */
    CHECK(run_gen(gen, "completion", comp, NULL) == 0, "edgewise_gen completion failed");
    CHECK(run_gen(gen, "man", committed_man, man) == 0, "edgewise_gen man failed");
    same_file(committed_comp, comp, "completion");
    same_file(committed_man, man, "man page");

    /* 2. no command has two rows of one option */
    int twice = 0;
    for (int i = 0; i < cli_noptions; i++)
        for (int j = i + 1; j < cli_noptions; j++)
            if ((cli_options[i].cmds & cli_options[j].cmds) && strcmp(cli_options[i].name, cli_options[j].name) == 0) {
                fprintf(stderr, "rows %d and %d: %s twice for one command\n", i, j, cli_options[i].name);
                twice++;
            }
    CHECK(twice == 0, "%d options have two rows for one command", twice);

    /* 3. every command's --help lists its options; the SYNOPSIS names every form */
    char *mantext = slurp(committed_man);
    ew_t_run *r = malloc(sizeof *r);
    for (int c = 0; r && c < CLI_NCMDS; c++) {
        const cli_command *cc = &cli_commands[c];
        char want[128];
        snprintf(want, sizeof want, ".B edgewise %s\n", cc->form);
        for (char *p = want; *p; p++)
            if (*p == '-') {  /* roff's \- */
                memmove(p + 1, p, strlen(p) + 1);
                *p++ = '\\';
            }
        CHECK(mantext && strstr(mantext, want), "SYNOPSIS lacks '%s'", cc->form);
        if (c == CLI_HELP) continue;
        const char *args[5] = { cc->name, NULL, NULL, NULL, NULL };
        int n = 1;
        if (strchr(cc->form, ' ')) args[n++] = strchr(cc->form, ' ') + 1;
        args[n] = "--help";
        ew_t_run_cli(r, tmp, args);
        if (r->status != 0 && strstr(r->err, "without SDL2")) {
            fprintf(stderr, "%s --help: this build has no viewer, not checked\n", cc->form);
            continue;
        }
        CHECK(r->status == 0, "%s --help: exit %d: %s", cc->form, r->status, r->err);
        for (int k = 0; k < cli_noptions; k++) {
            const cli_option *o = &cli_options[k];
            if (!(o->cmds & CLI_BIT(c)) || strcmp(o->name, "--help") == 0) continue;
            char line[96];
            snprintf(line, sizeof line, "  %s%s", o->name, o->metavar ? " " : "");
            CHECK(strstr(r->out, line) != NULL, "%s --help does not list %s", cc->form, o->name);
        }
    }

    /* 4. the completion offers every --hsr method, and every command */
    char *comptext = slurp(committed_comp);
    const char *arm = comptext ? strstr(comptext, ":--hsr") : NULL;
    const char *eol = arm ? strstr(arm, ";;") : NULL;
    CHECK(arm && eol, "completion: no arm for --hsr");
    for (int m = 0; arm && eol && ew_hsr_name((ew_hsr_method)m); m++) {
        /* the word in the arm's list: after a blank or the opening quote */
        const char *name = ew_hsr_name((ew_hsr_method)m);
        size_t n = strlen(name);
        int found = 0;
        for (const char *hit = arm; !found && (hit = strstr(hit, name)) && hit < eol; hit += n)
            found = (hit[-1] == ' ' || hit[-1] == '\'') && (hit[n] == ' ' || hit[n] == '\'');
        CHECK(found, "completion: --hsr does not offer %s", name);
    }
    /* 5. the unknown-command message names every command */
    const char *bad[] = { "frobnicate", NULL };
    if (r) ew_t_run_cli(r, tmp, bad);
    for (int c = 0; r && c < CLI_NCMDS; c++) {
        char word[48];
        snprintf(word, sizeof word, " %s", cli_commands[c].name);
        CHECK(r->status == 2 && strstr(r->err, word), "unknown command message lacks %s: %s", word + 1, r->err);
        CHECK(comptext && strstr(comptext, word), "completion lacks the command %s", word + 1);
    }
    free(r), free(mantext), free(comptext);
    char path[160];
    const char *files[] = { "edgewise.bash", "edgewise.1", "stdout.txt", "stderr.txt" };
    for (int k = 0; k < 4; k++) snprintf(path, sizeof path, "%s/%s", tmp, files[k]), remove(path);
    rmdir(tmp);
    return ew_t_finish();
}
