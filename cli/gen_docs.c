/*
 * gen_docs.c - edgewise_gen: the man page's SYNOPSIS and the bash
 * completion, written from the option table (cli/options.c).
 *
 *   edgewise_gen completion FILE     writes the bash completion to FILE
 *   edgewise_gen man IN OUT          IN with the part between the SYNOPSIS
 *                                    markers rewritten, to OUT (may be IN)
 *
 * `make cli_docs` runs both on completion/edgewise.bash and docs/edgewise.1;
 * tests/test_cli_table.c runs them to a temporary folder and fails when the
 * committed files differ.
 */
#include "cli.h"
#include "options.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAN_BEGIN ".\\\" BEGIN SYNOPSIS: written by edgewise_gen (make cli_docs) from cli/options.c\n"
#define MAN_END ".\\\" END SYNOPSIS\n"

/* options.c reports its parser's errors through it. */
void error_line(const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    fputs("edgewise_gen: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

/* ---- the man page's SYNOPSIS ------------------------------------------------ */

/* s with every '-' as roff's "\-". */
static void roff(FILE *f, const char *s, size_t n) {
    for (size_t i = 0; i < n && s[i]; i++) {
        if (s[i] == '-') fputs("\\-", f);
        else fputc(s[i], f);
    }
}

static int is_meta(const char *s) { return s[0] >= 'A' && s[0] <= 'Z'; }

/* One word of a synopsis alternative, as roff macros. */
static void synopsis_word(FILE *f, const char *w, size_t n, const char *next, size_t nn) {
    if (w[0] == '[') {
        const char *close = memchr(w, ']', n);
        size_t in = close ? (size_t)(close - w - 1) : n - 1;
        const char *inner = w + 1, *rest = close ? close + 1 : w + n;
        size_t nrest = (size_t)(w + n - rest);
        const char *sp = memchr(inner, ' ', in);
        if (in == 7 && strncmp(inner, "options", 7) == 0) {
            fprintf(f, ".RI [ options ]%.*s\n", (int)nrest, rest);
        } else if (sp) {
            fputs(".RB [ ", f);
            roff(f, inner, (size_t)(sp - inner));
            fprintf(f, "\n.IR %.*s ]%.*s\n", (int)(in - (size_t)(sp - inner) - 1), sp + 1, (int)nrest, rest);
        } else {
            fputs(".RB [ ", f);
            roff(f, inner, in);
            fprintf(f, " ]%.*s\n", (int)nrest, rest);
        }
        return;
    }
    (void)next, (void)nn;
    if (w[0] == '-') {
        fputs(".B ", f);
        roff(f, w, n);
        fputc('\n', f);
        return;
    }
    /* MAP, MAP..., MAP|DIR|PAK...: italic names, roman separators */
    if (!memchr(w, '|', n) && !memchr(w, '.', n)) {
        fprintf(f, ".I %.*s\n", (int)n, w);
        return;
    }
    fputs(".IR", f);
    size_t i = 0;
    while (i < n) {
        size_t j = i;
        int meta = is_meta(w + i);
        while (j < n && (meta ? (w[j] != '|' && w[j] != '.') : !is_meta(w + j))) j++;
        fprintf(f, " %.*s", (int)(j - i), w + i);
        i = j;
    }
    fputc('\n', f);
}

/* The synopsis's words: a bracket group is one word ("[--data DIR]..."). */
static void synopsis_line(FILE *f, const char *form, const char *s, size_t n) {
    fputs(".B edgewise ", f);
    roff(f, form, strlen(form));
    fputc('\n', f);
    size_t i = 0;
    while (i < n) {
        while (i < n && s[i] == ' ') i++;
        if (i >= n) break;
        size_t j = i;
        if (s[i] == '[') {
            while (j < n && s[j] != ']') j++;
            while (j < n && s[j] != ' ') j++;
        } else {
            while (j < n && s[j] != ' ') j++;
        }
        synopsis_word(f, s + i, j - i, s + j, n - j);
        i = j;
    }
}

static void write_synopsis(FILE *f) {
    fputs(MAN_BEGIN, f);
    for (int c = 0; c < CLI_NCMDS; c++) {
        const cli_command *cc = &cli_commands[c];
        if (c == CLI_HELP) {
            fputs(".B edgewise help\n|\n.B \\-\\-help\n.br\n.B edgewise \\-\\-version\n", f);
            continue;
        }
        for (const char *s = cc->synopsis;;) {
            size_t n = strcspn(s, "\n");
            synopsis_line(f, cc->form, s, n);
            fputs(".br\n", f);
            if (!s[n]) break;
            s += n + 1;
        }
    }
    fputs(MAN_END, f);
}

static char *slurp(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    size_t got;
    while (buf && (got = fread(buf + n, 1, cap - n - 1, f)) > 0) {
        n += got;
        if (n + 1 == cap) {
            char *nb = realloc(buf, cap *= 2);
            if (!nb) free(buf);
            buf = nb;
        }
    }
    fclose(f);
    if (buf) buf[n] = '\0';
    return buf;
}

static int gen_man(const char *in, const char *out) {
    char *text = slurp(in);
    if (!text) {
        error_line("%s: cannot read", in);
        return 1;
    }
    char *b = strstr(text, MAN_BEGIN), *e = b ? strstr(b, MAN_END) : NULL;
    if (!b || !e) {
        error_line("%s: no SYNOPSIS markers", in);
        free(text);
        return 1;
    }
    FILE *f = fopen(out, "wb");
    if (!f) {
        error_line("%s: cannot write", out);
        free(text);
        return 1;
    }
    fwrite(text, 1, (size_t)(b - text), f);
    write_synopsis(f);
    fputs(e + strlen(MAN_END), f);
    free(text);
    return fclose(f) == 0 ? 0 : 1;
}

/* ---- the bash completion ---------------------------------------------------- */

/* The completion's word for command c: the polyhedra forms are told apart
 * by their MAP. */
static const char *comp_name(int c) {
    return c == CLI_RENDER_POLYHEDRA ? "render-polyhedra" : c == CLI_VIEW_POLYHEDRA ? "view-polyhedra"
                                                                                    : cli_commands[c].name;
}

static void value_action(FILE *f, const cli_option *o) {
    switch (o->arg) {
    case CLI_ARG_WORD:
        fprintf(f, "COMPREPLY=($(compgen -W '%s' -- \"$cur\")); return 0 ;;\n", o->words);
        break;
    case CLI_ARG_FILE:
        fputs("compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- \"$cur\")); return 0 ;;\n", f);
        break;
    case CLI_ARG_DIR:
        fputs("compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -d -- \"$cur\")); return 0 ;;\n", f);
        break;
    case CLI_ARG_FILE_OR_WORD:
        fprintf(f, "compopt -o filenames 2>/dev/null\n            COMPREPLY=($(compgen -W '%s' -- \"$cur\") "
                   "$(compgen -f -- \"$cur\")); return 0 ;;\n", o->words);
        break;
    default:
        fputs("return 0 ;;\n", f);
    }
}

static int gen_completion(const char *out) {
    FILE *f = fopen(out, "wb");
    if (!f) {
        error_line("%s: cannot write", out);
        return 1;
    }
    fputs("# bash completion for edgewise(1): commands, each command's options, the\n"
          "# values of the options that take a word from a fixed list, and files where\n"
          "# a file or directory is expected.  Installed as\n"
          "# share/bash-completion/completions/edgewise; or `source` it.\n"
          "# Written by edgewise_gen (make cli_docs) from the option table, cli/options.c:\n"
          "# edit that, not this.\n"
          "\n"
          "_edgewise()\n"
          "{\n"
          "    local cur=${COMP_WORDS[COMP_CWORD]} prev= cmd=${COMP_WORDS[1]-} w\n"
          "    [ \"$COMP_CWORD\" -gt 0 ] && prev=${COMP_WORDS[COMP_CWORD-1]}\n"
          "    COMPREPLY=()\n"
          "\n", f);
    fputs("    local commands='", f);
    for (int c = 0, first = 1; c < CLI_NCMDS; c++)
        if (!strcmp(cli_commands[c].form, cli_commands[c].name)) fprintf(f, "%s%s", first ? "" : " ", cli_commands[c].name), first = 0;
    fputs("'\n"
          "    if [ \"$COMP_CWORD\" -le 1 ]; then\n"
          "        COMPREPLY=($(compgen -W \"$commands --help --version\" -- \"$cur\"))\n"
          "        return 0\n"
          "    fi\n"
          "    # render and view of builtin:polyhedra have their own options\n"
          "    for w in \"${COMP_WORDS[@]:2}\"; do\n"
          "        [ \"$w\" = builtin:polyhedra ] && case $cmd in render|view) cmd=$cmd-polyhedra ;; esac\n"
          "    done\n"
          "\n"
          "    # The values of options.\n"
          "    case $cmd:$prev in\n", f);
    /* one arm per row that takes a value: its commands' patterns */
    for (int k = 0; k < cli_noptions; k++) {
        const cli_option *o = &cli_options[k];
        if (!o->metavar || o->arg == CLI_ARG_NUMBER) continue;
        fputs("        ", f);
        int first = 1;
        for (int c = 0; c < CLI_NCMDS; c++) {
            if (!(o->cmds & CLI_BIT(c))) continue;
            fprintf(f, "%s%s:%s", first ? "" : "|", comp_name(c), o->name);
            first = 0;
        }
        fputs(")\n            ", f);
        value_action(f, o);
    }
    /* numbers, sizes and lists: nothing to offer */
    fputs("        ", f);
    for (int k = 0, n = 0; k < cli_noptions; k++) {
        const cli_option *o = &cli_options[k];
        if (o->arg != CLI_ARG_NUMBER) continue;
        for (int c = 0; c < CLI_NCMDS; c++) {
            if (!(o->cmds & CLI_BIT(c))) continue;
            if (n && n % 4 == 0) fputs("|\\\n        ", f);
            else if (n) fputc('|', f);
            fprintf(f, "%s:%s", comp_name(c), o->name);
            n++;
        }
    }
    fputs(")\n            return 0 ;;\n", f);
    fputs("    esac\n"
          "\n"
          "    local opts\n"
          "    case $cmd in\n", f);
    for (int c = 0; c < CLI_NCMDS; c++) {
        if (c == CLI_HELP) continue;
        fprintf(f, "        %s) opts='", comp_name(c));
        int first = 1, col = 0;
        for (int k = 0; k < cli_noptions; k++) {
            const cli_option *o = &cli_options[k];
            if (!(o->cmds & CLI_BIT(c))) continue;
            if (col > 70) fputs("\n                  ", f), col = 0;
            else if (!first) fputc(' ', f);
            fputs(o->name, f);
            col += (int)strlen(o->name) + 1;
            first = 0;
        }
        fputs("' ;;\n", f);
    }
    fputs("        *) return 0 ;;\n"
          "    esac\n"
          "    if [[ $cur == -* ]]; then\n"
          "        COMPREPLY=($(compgen -W \"$opts\" -- \"$cur\"))\n"
          "    elif [ \"$cmd\" != demo ]; then\n"
          "        # MAP: the built-in scene, .bsp files, directories to walk into.\n"
          "        compopt -o filenames 2>/dev/null\n"
          "        COMPREPLY=($(compgen -W 'builtin builtin:polyhedra' -- \"$cur\")\n"
          "                   $(compgen -d -- \"$cur\")\n"
          "                   $(compgen -f -X '!*.bsp' -- \"$cur\"))\n"
          "    fi\n"
          "    return 0\n"
          "}\n"
          "complete -F _edgewise edgewise\n", f);
    return fclose(f) == 0 ? 0 : 1;
}

int main(int argc, char **argv) {
    if (argc == 3 && strcmp(argv[1], "completion") == 0) return gen_completion(argv[2]);
    if (argc == 4 && strcmp(argv[1], "man") == 0) return gen_man(argv[2], argv[3]);
    fputs("usage: edgewise_gen completion FILE\n       edgewise_gen man IN OUT\n", stderr);
    return 2;
}
