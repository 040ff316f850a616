/*
 * cli.h - helpers of cli/edgewise.c shared with the commands that live in
 * their own files (cmd_*.c), so every command parses and reports alike.
 */
#ifndef EW_CLI_H
#define EW_CLI_H

#include <stddef.h>
#include <stdio.h>

#if defined(__GNUC__)
#define EW_CLI_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define EW_CLI_PRINTF(a, b)
#endif

/* One "edgewise: <message>" line on stderr, control characters replaced. */
void error_line(const char *fmt, ...) EW_CLI_PRINTF(1, 2);
/* Whole decimal numbers, no blanks; 0 or -1 (nothing printed). */
int  parse_long(const char *s, long *out);
/* "WxH" within the renderer's limits; 0 or -1 (error printed). */
int  parse_size(const char *s, int *w, int *h);
/* MAP is the word 'builtin'. */
int  is_builtin(const char *map);
/* "maps/e1m1.bsp" -> "e1m1". */
void map_basename(const char *map, char *out, size_t size);
/* A JSON string / number (null for inf and nan). */
void json_string(FILE *f, const char *s);
void json_number(FILE *f, double v);

/* edgewise bench (cli/cmd_bench.c): argv[1] is "bench". */
int cmd_bench(int argc, char **argv);
/* edgewise soak (cli/cmd_soak.c): argv[1] is "soak". */
int cmd_soak(int argc, char **argv);

#endif
