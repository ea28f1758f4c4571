/* One command-line grammar for every command (brdfit's subcommands and brdfit-synth).
 * Each command declares its options once, in tables of cli_option grouped under titles;
 * parsing, --help, the man pages and bash completion all come from those tables.
 *
 * Grammar: long options take "--name value" or "--name=value", short ones "-m value" or
 * "-mvalue"; short flags bundle ("-qv"); "--" ends the options; a lone "-" is an operand
 * (standard input or output). Every command also takes -h/--help (exit 0), -q/--quiet and
 * -v/--verbose. A bad option gets one line and exit 2. */
#ifndef BRDFIT_CLI_H
#define BRDFIT_CLI_H

#include <stddef.h>
#include <stdio.h>

#include "brdfit/options.h"

/* Options are bound to their variables (after git's parse-options): each entry says where
 * its value goes, in the struct its group fills (the group's "target", given to
 * cli_take), and how it is read, so an option added to a table cannot silently mean
 * something else; brdfit-doc refuses a table with an unbound option at build time. */
typedef enum cli_kind {
    CLI_UNBOUND = 0, /* never in a finished table */
    CLI_FLAG,        /* an int set to .lo */
    CLI_STRING,      /* a const char *: the value as given (checked where it is used) */
    CLI_INT,         /* an int: an integer in [.lo, .hi] (args_int's strict digits) */
    CLI_NUMBER,      /* a double: a number in [.lo, .hi] */
    CLI_CALL,        /* .take reads it */
    CLI_LIBRARY,     /* a run option of the library (brdfit/options.h): declared there, by
                        name, with its value's name, help and completion, and set there
                        (bf_options_set) into the bf_options the group points at */
} cli_kind;

typedef struct cli_option cli_option;

/* Takes option o's value (NULL for a flag) into target, the group's struct: 0, or -1
 * after a one-line error starting with cmd. */
typedef int (*cli_take_fn)(void *target, const cli_option *o, const char *value, const char *cmd);

struct cli_option {
    const char *name; /* long form with its dashes: "--model" */
    char short_name;  /* 'm', or 0 */
    const char *arg;  /* the value's name in help ("FILE", "N|all"); NULL for a flag */
    const char *help; /* help text; '\n' starts a continuation line */
    /* What a shell completes for the value: NULL nothing, "file", "dir", a kind the
     * generator names from a registry ("model", "method", "local_method"), or choices
     * "a|b|c" (when NULL, taken from arg if it lists choices). */
    const char *complete;
    /* The binding (CLI_* macros below). */
    cli_kind kind;
    size_t at;        /* offset of the variable in the target */
    double lo, hi;    /* CLI_INT, CLI_NUMBER: the range; CLI_FLAG: lo is the value */
    const char *what; /* CLI_INT, CLI_NUMBER: the range for the error ("degrees in (0, 90]");
                         NULL: "an integer from LO to HI" */
    cli_take_fn take; /* CLI_CALL */
};

/* The bindings, after an entry's five descriptive fields: TYPE is the target struct. */
#define CLI_SETS(TYPE, FIELD, VALUE) .kind = CLI_FLAG, .at = offsetof(TYPE, FIELD), .lo = (VALUE)
#define CLI_STRING_AT(TYPE, FIELD) .kind = CLI_STRING, .at = offsetof(TYPE, FIELD)
#define CLI_INT_AT(TYPE, FIELD, LO, HI) .kind = CLI_INT, .at = offsetof(TYPE, FIELD), .lo = (LO), .hi = (HI)
#define CLI_NUMBER_AT(TYPE, FIELD, LO, HI, WHAT)                                                                       \
    .kind = CLI_NUMBER, .at = offsetof(TYPE, FIELD), .lo = (LO), .hi = (HI), .what = (WHAT)
#define CLI_CALLS(FN) .kind = CLI_CALL, .take = (FN)
/* A library run option in a command's own table, by its command-line name: the rest of
 * its entry comes from the library's table, for the group's task. */
#define CLI_LIB(NAME)                                                                                                  \
    {                                                                                                                  \
        NAME, 0, NULL, NULL, NULL, .kind = CLI_LIBRARY                                                                 \
    }

typedef struct cli_group {
    const char *title; /* "reading", "fitting", ...; NULL: the command's own */
    const cli_option *options;
    int n;
    /* Library options (brdfit/options.h). library: a group of the library's table, whose
     * options (those task takes; 0: any) make this group's entries, in the library's
     * order. CLI_LIB entries and such a group take their values into the bf_options
     * pointed at by the bf_options * at offset options_at in the group's target. */
    const char *library;
    unsigned task;
    size_t options_at;
} cli_group;

#define CLI_GROUP(title, table)                                                                                        \
    {                                                                                                                  \
        title, table, (int)(sizeof table / sizeof table[0]), NULL, 0, 0                                                \
    }
/* A group with CLI_LIB entries: TYPE's FIELD is the bf_options * they are set into. */
#define CLI_GROUP_OPTIONS(title, table, task, TYPE, FIELD)                                                             \
    {                                                                                                                  \
        title, table, (int)(sizeof table / sizeof table[0]), NULL, task, offsetof(TYPE, FIELD)                         \
    }
/* The library's group NAME (under that title) for task: its target is a bf_options *. */
#define CLI_LIBRARY_GROUP(NAME, task)                                                                                  \
    {                                                                                                                  \
        NAME, NULL, 0, NAME, task, 0                                                                                   \
    }

typedef struct cli_command {
    const char *tool;     /* "brdfit" or "brdfit-synth" */
    const char *name;     /* "fit"; NULL for a tool without subcommands */
    const char *synopsis; /* after the command name: "DATA -m MODEL[,MODEL...] [options]" */
    const char *summary;  /* one line, lower case, for lists and the man page's NAME */
    /* Paragraphs for --help and the man page (blank line between paragraphs), or NULL. */
    const char *description;
    const char *operands;           /* completion of operands: "file", "dir" or NULL */
    const cli_group *const *groups; /* the command's options, by group */
    int ngroups;
} cli_command;

/* One option or operand of a parsed command line, in order. */
typedef struct cli_arg {
    const char *name;         /* the option's long form ("--model"), or NULL for an operand */
    const char *value;        /* the option's value (NULL for a flag), or the operand */
    const cli_option *option; /* its entry (NULL for an operand) */
    int group;                /* its group's index in the command's groups */
} cli_arg;

typedef struct cli_args {
    cli_arg *v;
    int n;
} cli_args;

enum { CLI_OK = 0, CLI_EXIT = 1, CLI_USAGE = 2 };

/* Parses argv[1..argc-1] (argv[0] is the command's name) against c's tables into a
 * (freed with cli_args_free). CLI_OK; CLI_EXIT after printing --help to stdout (exit
 * 0); CLI_USAGE after printing one line to stderr (exit 2). */
int cli_parse(const cli_command *c, int argc, char **argv, cli_args *a);
/* Option words that are not a command line (a batch manifest's): words[0..n-1] parsed as
 * cli_parse does, except that --help, --quiet and --verbose are not options here (they
 * would act on the process) and messages start with where ("brdfit batch: m.txt: line
 * 2"). CLI_OK, or CLI_USAGE after one line on stderr. */
int cli_parse_words(const cli_command *c, int n, char **words, cli_args *a, const char *where);
void cli_args_free(cli_args *a);

#define CLI_COUNT(array) ((int)(sizeof(array) / sizeof(array)[0]))

/* Takes the parsed options of c into their variables, in command-line order:
 * targets[g] is the struct c->groups[g] fills (groups may share one; ntargets must be
 * c->ngroups, so a table and its targets cannot drift apart); each operand goes
 * to operand(ctx, value, cmd) (NULL: the command takes none, and one is bad usage:
 * "CMD: unexpected argument 'X' (see CMD --help)"). Messages start with cmd.
 * 0, or -1 after a one-line error (the caller exits 2). */
int cli_take(const cli_command *c, void *const *targets, int ntargets, const cli_args *a,
             int (*operand)(void *ctx, const char *value, const char *cmd), void *ctx, const char *cmd);

/* One option, by long name, if group g has it: taken into target (g's struct) as
 * cli_take would; 1 when taken, 0 when g has no such option, -1 after a one-line error. */
int cli_group_take(const cli_group *g, void *target, const char *name, const char *value, const char *cmd);

/* 0 when every option of c is bound; otherwise -1 after naming the first that is not
 * (brdfit-doc checks every command at build time). */
int cli_check_bound(const cli_command *c);

/* The option of c (or a common one) whose long form is name[0..len-1], or NULL. */
const cli_option *cli_find(const cli_command *c, const char *name, size_t len);

/* The command's full name for messages: "brdfit fit", "brdfit-synth". */
const char *cli_title(const cli_command *c, char *buf, size_t len);

/* --help text: usage line, description, the options by group. */
void cli_help(const cli_command *c, FILE *out);
/* A man page (roff) for c, section 1. `see_also` is a comma-separated list of pages. */
void cli_man(const cli_command *c, const char *version, const char *see_also, FILE *out);

/* A bash completion script for a tool: its subcommands cmds[0..n-1], or cmds[0] alone
 * for a tool without subcommands (name NULL). Values of a named kind ("model",
 * "method") complete to the '|'-separated words words_of(kind) returns (NULL: none). */
void cli_completion(const cli_command *const *cmds, int n, const char *(*words_of)(const char *kind), FILE *out);

/* What the last cli_parse saw of --quiet and --verbose (for the whole process). */
int cli_verbose(void);
int cli_quiet(void);

/* Prints "CMD: message" on stderr when --verbose was given. */
void cli_note(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
