/*
 * options.h - the command line's one option table (cli/options.c).
 *
 * Every command (and the two builtin:polyhedra forms) and every option each
 * takes is written down once, in cli/options.c: its name, its argument
 * (none, or a metavariable and what kind of value), its help text and the
 * commands that take it.  From the table come
 *   - each command's option lines in its --help (cli_print_options),
 *   - the one parser every command runs (cli_parse): "--", "--name",
 *     "--name=VALUE", "--name VALUE", and the messages for an unknown
 *     option, one that does not apply, a missing or unwanted value,
 *   - the unknown-command message (cli_unknown_command), listing every
 *     command,
 *   - the man page's SYNOPSIS and the bash completion, written by
 *     cli/gen_docs.c (`make cli_docs`; tests/test_cli_table.c checks the
 *     committed files against it).
 */
#ifndef EW_CLI_OPTIONS_H
#define EW_CLI_OPTIONS_H

#include <stdio.h>

/* The commands, and the two forms with their own options. */
typedef enum cli_cmd {
    CLI_RENDER, CLI_DEMO, CLI_VIEWS, CLI_INFO, CLI_BENCH, CLI_HSR, CLI_SOAK, CLI_SHOTS, CLI_FLY,
    CLI_VIEW, CLI_TIMEDEMO, CLI_RENDER_POLYHEDRA, CLI_VIEW_POLYHEDRA, CLI_HELP, CLI_NCMDS
} cli_cmd;
#define CLI_BIT(c) (1u << (c))

typedef struct cli_command {
    const char *name;      /* the word after edgewise: "render" */
    const char *form;      /* how --help and messages name it: "render builtin:polyhedra" */
    const char *synopsis;  /* the man page's SYNOPSIS lines after the form, '\n' between
                            * alternatives (each its own line): "MAP [options]" */
    const char *summary;   /* one line of `edgewise help` ("" for the forms) */
} cli_command;
extern const cli_command cli_commands[CLI_NCMDS];

/* What an option's value is: for the completion (files, folders, words)
 * and the man page; every value is checked by its command. */
typedef enum cli_arg {
    CLI_ARG_NONE,    /* a flag */
    CLI_ARG_NUMBER,  /* numbers, sizes, lists of them: nothing to complete */
    CLI_ARG_WORD,    /* one of `words` */
    CLI_ARG_FILE,    /* a file name */
    CLI_ARG_DIR,     /* a folder */
    CLI_ARG_FILE_OR_WORD  /* one of `words`, or a file name */
} cli_arg;

typedef struct cli_option {
    const char *name;      /* "--size" */
    const char *metavar;   /* "WxH"; NULL for a flag */
    cli_arg     arg;
    const char *words;     /* CLI_ARG_WORD: the values, blank-separated */
    unsigned    cmds;      /* CLI_BIT()s of the commands that take it with this help */
    int         draw;      /* a drawing option (what is drawn, cli/draw_options.c) */
    const char *help;      /* what it does; '\n' starts a continuation line */
    const char *rule;      /* drawing options: the value's rule ("METAVAR must be RULE") */
} cli_option;
extern const cli_option cli_options[];
extern const int cli_noptions;

/* The command named name (a form's name is its command's), or -1. */
int cli_command_of(const char *name);
/* The row of option name (up to len characters, or the whole string when
 * len < 0) for command cmd, or NULL. */
const cli_option *cli_find(cli_cmd cmd, const char *name, int len);
/* Prints cmd's own option lines (draw 0) or its drawing options (draw 1)
 * as --help shows them. */
void cli_print_options(FILE *f, cli_cmd cmd, int draw);
/* Prints a command's help text, its own option lines where the text has
 * CLI_OPTIONS_HERE (a line of its own). */
#define CLI_OPTIONS_HERE "@OPTIONS@\n"
void cli_print_help(FILE *f, cli_cmd cmd, const char *text);
/* "unknown command 'X' (commands: render, demo, ...)" on stderr. */
void cli_unknown_command(const char *name);

/* One step through a command's arguments, from argv[first].  Returns
 * CLI_END, CLI_POSITIONAL (*value: the argument), CLI_OPTION (*opt: its
 * row, *value its value or NULL for a flag; --help/-h is the row of
 * "--help") or -1 after one error line ("CMD: unknown option '--x' (see
 * edgewise CMD --help)", "... does not apply here ...", "... needs a
 * value", "... takes no value"). */
enum { CLI_END = 0, CLI_OPTION = 1, CLI_POSITIONAL = 2 };
typedef struct cli_parser {
    cli_cmd cmd;
    int     argc, i;
    char  **argv;
    int     only_positional;
} cli_parser;
void cli_parser_init(cli_parser *p, cli_cmd cmd, int argc, char **argv, int first);
int  cli_parse(cli_parser *p, const cli_option **opt, const char **value);
/* The game directories to search: data ("DIR" of --data, NULL if none)
 * behind the --game DIR that cli_parse took (the parser keeps it for
 * every command that has it), as a search list "GAME:DATA" (ew_fs_create);
 * data itself without --game. */
const char *cli_search_path(const char *data);
/* opt is the option named name. */
int  cli_is(const cli_option *opt, const char *name);

#endif
