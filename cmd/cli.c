/* The command-line grammar and the texts made from the option tables (cli.h). */
#include "cli.h"

#include "args.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* Options every command takes, listed last in --help; the parser itself acts on them
 * (common_option), so they are bound to no command's variable. */
static const cli_option common[] = {
    {"--help", 'h', NULL, "this help, then exit", NULL, .kind = CLI_UNBOUND},
    {"--quiet", 'q', NULL, "no progress or summaries on the terminal (errors still)", NULL, .kind = CLI_UNBOUND},
    {"--verbose", 'v', NULL, "say what is read and done, on stderr", NULL, .kind = CLI_UNBOUND},
};
static const cli_group common_group = CLI_GROUP("common", common);

/* ---- Entries from the library's table ------------------------------------------------ */

/* Library options take their arg, help and completion from the library's table; these
 * are the groups' resolved entries, made once per group for the process. */
typedef struct resolved {
    const cli_group *g;
    cli_option *v;
    int n;
} resolved;
static resolved resolved_groups[64];
static int nresolved;

/* "--max-theta" for the library's "max_theta" (kept for the process). */
static const char *long_name(const char *keyword)
{
    size_t n = strlen(keyword);
    char *s = malloc(n + 3);
    if (!s)
        return keyword;
    s[0] = s[1] = '-';
    for (size_t k = 0; k <= n; k++)
        s[k + 2] = keyword[k] == '_' ? '-' : keyword[k];
    return s;
}

static void fill_from_library(cli_option *o, const bf_option *d)
{
    o->arg = d->arg;
    o->help = d->help;
    o->complete = d->complete;
    o->kind = CLI_LIBRARY;
}

/* Group g's entries: its table, with library entries filled in, or the library group's. */
static const cli_option *entries(const cli_group *g, int *n)
{
    int lib = g->library != NULL;
    for (int k = 0; !lib && k < g->n; k++)
        lib = g->options[k].kind == CLI_LIBRARY;
    if (!lib) {
        *n = g->n;
        return g->options;
    }
    for (int i = 0; i < nresolved; i++)
        if (resolved_groups[i].g == g) {
            *n = resolved_groups[i].n;
            return resolved_groups[i].v;
        }
    int count = g->n;
    for (int i = 0; g->library && i < bf_option_count(); i++)
        count++;
    cli_option *v = calloc((size_t)(count ? count : 1), sizeof *v);
    if (!v || nresolved == (int)(sizeof resolved_groups / sizeof resolved_groups[0])) {
        free(v);
        *n = 0;
        return NULL;
    }
    int m = 0;
    for (int k = 0; k < g->n; k++) {
        v[m] = g->options[k];
        const bf_option *d = v[m].kind == CLI_LIBRARY ? bf_option_find(v[m].name, g->task) : NULL;
        if (d)
            fill_from_library(&v[m], d);
        m++;
    }
    for (int i = 0; g->library && i < bf_option_count(); i++) {
        const bf_option *d = bf_option_get(i);
        if (strcmp(d->group, g->library) || (g->task && !(d->tasks & g->task)) || bf_option_find(d->name, g->task) != d)
            continue;
        v[m] = (cli_option){long_name(d->name), 0, NULL, NULL, NULL, .kind = CLI_LIBRARY};
        fill_from_library(&v[m], d);
        m++;
    }
    resolved_groups[nresolved++] = (resolved){g, v, m};
    *n = m;
    return v;
}

static int verbosity = 1;

int cli_verbose(void)
{
    return verbosity > 1;
}

int cli_quiet(void)
{
    return verbosity < 1;
}

void cli_note(const char *cmd, const char *fmt, ...)
{
    if (verbosity < 2)
        return;
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s: ", cmd);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

const char *cli_title(const cli_command *c, char *buf, size_t len)
{
    if (c->name)
        snprintf(buf, len, "%s %s", c->tool, c->name);
    else
        snprintf(buf, len, "%s", c->tool);
    return buf;
}

/* The option with this long name (with its dashes, up to len) or short letter; the
 * common options (help, quiet, verbose) only when common. */
static const cli_option *find_in(const cli_command *c, const char *name, size_t len, char letter, int common,
                                 int *group)
{
    for (int g = common ? -1 : 0; g < c->ngroups; g++) {
        const cli_group *grp = g < 0 ? &common_group : c->groups[g];
        int n;
        const cli_option *v = entries(grp, &n);
        for (int k = 0; k < n; k++) {
            const cli_option *o = &v[k];
            if (name ? strlen(o->name) == len && !strncmp(o->name, name, len) : o->short_name == letter) {
                *group = g;
                return o;
            }
        }
    }
    return NULL;
}

const cli_option *cli_find(const cli_command *c, const char *name, size_t len)
{
    int g;
    return find_in(c, name, len, 0, 1, &g);
}

/* One more option (o, in group g) or operand (o NULL) of the command line. */
static int push(cli_args *a, const cli_option *o, int g, const char *value)
{
    cli_arg *v = realloc(a->v, (size_t)(a->n + 1) * sizeof *v);
    if (!v)
        return 0;
    a->v = v;
    a->v[a->n] = (cli_arg){o ? o->name : NULL, value, o, o ? g : -1};
    a->n++;
    return 1;
}

/* Applies an option the parser owns (help, quiet, verbose); 1 when it was one. */
static int common_option(const cli_option *o, int *help)
{
    if (o == &common[0])
        *help = 1;
    else if (o == &common[1])
        verbosity = 0;
    else if (o == &common[2])
        verbosity = 2;
    else
        return 0;
    return 1;
}

/* argv[first..argc-1] parsed by c's options into a. where NULL: a command line, whose
 * messages start with the command's name and point to its --help; else words that are
 * not a command line (cli_parse_words): messages start with where, and the common
 * options are not taken. */
static int parse(const cli_command *c, int argc, char **argv, int first, cli_args *a, const char *where)
{
    char name[64], see[96] = "";
    const char *title = where ? where : cli_title(c, name, sizeof name);
    if (!where)
        snprintf(see, sizeof see, " (see %s --help)", title);
    memset(a, 0, sizeof *a);
    int help = 0, options = 1;
    for (int i = first; i < argc; i++) {
        const char *s = argv[i];
        if (!options || s[0] != '-' || !s[1]) { /* an operand, "-" included */
            if (!push(a, NULL, -1, s))
                goto nomem;
            continue;
        }
        if (!strcmp(s, "--")) {
            options = 0;
            continue;
        }
        if (s[1] == '-') { /* --name, --name=value, --name value */
            const char *eq = strchr(s, '=');
            size_t len = eq ? (size_t)(eq - s) : strlen(s);
            int g;
            const cli_option *o = find_in(c, s, len, 0, !where, &g);
            if (!o) {
                fprintf(stderr, "%s: unknown option '%.*s'%s\n", title, (int)(len > 64 ? 64 : len), s, see);
                goto usage;
            }
            if (!o->arg && eq) {
                fprintf(stderr, "%s: %s takes no value\n", title, o->name);
                goto usage;
            }
            const char *value = eq ? eq + 1 : NULL;
            if (o->arg && !eq) {
                if (i + 1 >= argc) {
                    fprintf(stderr, "%s: %s needs a value (%s)\n", title, o->name, o->arg);
                    goto usage;
                }
                value = argv[++i];
            }
            if (!common_option(o, &help) && !push(a, o, g, value))
                goto nomem;
            continue;
        }
        /* -x, -xVALUE, -x VALUE, and flags bundled: -qv */
        for (const char *p = s + 1; *p; p++) {
            int g;
            const cli_option *o = find_in(c, NULL, 0, *p, !where, &g);
            if (!o) {
                if (p == s + 1)
                    fprintf(stderr, "%s: unknown option '-%c'%s\n", title, *p, see);
                else
                    fprintf(stderr, "%s: unknown option '-%c' in '%.64s'%s\n", title, *p, s, see);
                goto usage;
            }
            const char *value = NULL;
            if (o->arg) {
                if (p[1])
                    value = p + 1;
                else if (i + 1 < argc)
                    value = argv[++i];
                else {
                    fprintf(stderr, "%s: -%c needs a value (%s)\n", title, *p, o->arg);
                    goto usage;
                }
            }
            if (!common_option(o, &help) && !push(a, o, g, value))
                goto nomem;
            if (o->arg)
                break;
        }
    }
    if (help) {
        cli_help(c, stdout);
        cli_args_free(a);
        return CLI_EXIT;
    }
    return CLI_OK;
nomem:
    fprintf(stderr, "%s: out of memory\n", title);
usage:
    cli_args_free(a);
    return CLI_USAGE;
}

int cli_parse(const cli_command *c, int argc, char **argv, cli_args *a)
{
    return parse(c, argc, argv, 1, a, NULL);
}

int cli_parse_words(const cli_command *c, int n, char **words, cli_args *a, const char *where)
{
    return parse(c, n, words, 0, a, where);
}

/* ---- Taking options into their variables ------------------------------------------ */

/* The integer and number kinds: the value in range, or the one-line error. */
static int take_number(void *var, const cli_option *o, const char *v, const char *cmd)
{
    char what[96];
    if (o->kind == CLI_INT) {
        long n;
        if (args_int(v, (long)o->lo, (long)o->hi, &n)) {
            *(int *)var = (int)n;
            return 0;
        }
        if (!o->what)
            snprintf(what, sizeof what, "an integer from %ld to %ld", (long)o->lo, (long)o->hi);
    } else {
        double d;
        if (args_number(v, o->lo, o->hi, &d)) {
            *(double *)var = d;
            return 0;
        }
        if (!o->what)
            snprintf(what, sizeof what, "a number from %g to %g", o->lo, o->hi);
    }
    fprintf(stderr, "%s: %s needs %s, got '%s'\n", cmd, o->name, o->what ? o->what : what, v);
    return -1;
}

static int take_one(void *target, const cli_group *g, const cli_option *o, const char *v, const char *cmd)
{
    char *var = (char *)target + o->at;
    int rc = 0;
    bf_error err;
    switch (o->kind) {
    case CLI_LIBRARY:
        if (bf_options_set(*(bf_options **)((char *)target + g->options_at), o->name, v, &err) != BF_OK) {
            fprintf(stderr, "%s: %s\n", cmd, err.msg);
            rc = -1;
        }
        break;
    case CLI_FLAG: *(int *)var = (int)o->lo; break;
    case CLI_STRING: *(const char **)var = v; break;
    case CLI_INT:
    case CLI_NUMBER: rc = take_number(var, o, v, cmd); break;
    case CLI_CALL: rc = o->take(target, o, v, cmd); break;
    default: fprintf(stderr, "%s: internal error: option %s is not bound to a variable\n", cmd, o->name); return -1;
    }
    return rc;
}

int cli_take(const cli_command *c, void *const *targets, int ntargets, const cli_args *a,
             int (*operand)(void *ctx, const char *value, const char *cmd), void *ctx, const char *cmd)
{
    if (ntargets != c->ngroups) {
        fprintf(stderr, "%s: internal error: %d option targets for %d groups\n", cmd, ntargets, c->ngroups);
        return -1;
    }
    for (int i = 0; i < a->n; i++) {
        const cli_arg *x = &a->v[i];
        if (!x->option) {
            if (!operand) {
                fprintf(stderr, "%s: unexpected argument '%s' (see %s --help)\n", cmd, x->value, cmd);
                return -1;
            }
            if (operand(ctx, x->value, cmd) != 0)
                return -1;
        } else if (take_one(targets[x->group], c->groups[x->group], x->option, x->value, cmd) != 0) {
            return -1;
        }
    }
    return 0;
}

int cli_group_take(const cli_group *g, void *target, const char *name, const char *value, const char *cmd)
{
    int n;
    const cli_option *v = entries(g, &n);
    for (int k = 0; k < n; k++)
        if (!strcmp(v[k].name, name))
            return take_one(target, g, &v[k], value, cmd) == 0 ? 1 : -1;
    return 0;
}

int cli_check_bound(const cli_command *c)
{
    char title[64];
    for (int g = 0; g < c->ngroups; g++) {
        int n;
        const cli_option *v = entries(c->groups[g], &n);
        for (int k = 0; k < n; k++) {
            const cli_option *o = &v[k];
            int ok = o->kind == CLI_FLAG || o->kind == CLI_STRING || o->kind == CLI_INT || o->kind == CLI_NUMBER ||
                     (o->kind == CLI_CALL && o->take) || (o->kind == CLI_LIBRARY && o->help);
            /* A flag binding has no value to read; an option without a value is a flag
             * or a callback (which reads none). */
            if (!ok || (o->kind == CLI_FLAG && o->arg) ||
                (!o->arg && o->kind != CLI_FLAG && o->kind != CLI_CALL && o->kind != CLI_LIBRARY)) {
                fprintf(stderr, "%s: option %s is not bound to a variable of its kind (cli.h)\n",
                        cli_title(c, title, sizeof title), o->name);
                return -1;
            }
        }
    }
    return 0;
}

void cli_args_free(cli_args *a)
{
    free(a->v);
    a->v = NULL;
    a->n = 0;
}

/* ---- --help ---------------------------------------------------------------------- */

#define HELP_COLUMN 29

static void help_option(const cli_option *o, FILE *out)
{
    char left[160];
    int n = o->short_name ? snprintf(left, sizeof left, "  -%c, %s", o->short_name, o->name)
                          : snprintf(left, sizeof left, "  %s", o->name);
    if (o->arg && n < (int)sizeof left)
        snprintf(left + n, sizeof left - (size_t)n, " %s", o->arg);
    fputs(left, out);
    int width = (int)strlen(left);
    if (width < HELP_COLUMN - 1)
        fprintf(out, "%*s", HELP_COLUMN - width, "");
    else
        fputs("   ", out);
    for (const char *h = o->help; *h; h++) {
        fputc(*h, out);
        if (*h == '\n')
            fprintf(out, "%*s", HELP_COLUMN, "");
    }
    fputc('\n', out);
}

static void help_group(const cli_group *g, FILE *out)
{
    int n;
    const cli_option *v = entries(g, &n);
    fprintf(out, "%s:\n", g->title ? g->title : "options");
    for (int k = 0; k < n; k++)
        help_option(&v[k], out);
}

/* Paragraphs filled to width columns (words never split). */
static void wrap(const char *text, int width, FILE *out)
{
    int col = 0;
    for (const char *p = text; *p;) {
        if (*p == '\n') { /* a paragraph break or a forced line */
            fputc('\n', out);
            col = 0;
            p++;
            continue;
        }
        if (*p == ' ') {
            p++;
            continue;
        }
        size_t len = strcspn(p, " \n");
        if (col > 0 && col + 1 + (int)len > width) {
            fputc('\n', out);
            col = 0;
        } else if (col > 0) {
            fputc(' ', out);
            col++;
        }
        fwrite(p, 1, len, out);
        col += (int)len;
        p += len;
    }
    if (col > 0)
        fputc('\n', out);
}

void cli_help(const cli_command *c, FILE *out)
{
    char title[64];
    fprintf(out, "usage: %s %s\n", cli_title(c, title, sizeof title), c->synopsis);
    fprintf(out, "%c%s.\n", c->summary[0] >= 'a' && c->summary[0] <= 'z' ? c->summary[0] - 'a' + 'A' : c->summary[0],
            c->summary + 1);
    if (c->description) {
        fputc('\n', out);
        wrap(c->description, 88, out);
    }
    fputc('\n', out);
    for (int g = 0; g < c->ngroups; g++)
        help_group(c->groups[g], out);
    help_group(&common_group, out);
    fputs("exit status: 0 done, 1 failure (data, fit, output), 2 bad usage\n", out);
}

/* ---- man pages --------------------------------------------------------------------- */

/* Text for roff: backslashes and dashes escaped, no line starting with '.' or '\''. */
static void roff(const char *s, FILE *out, int line_start)
{
    for (; *s; s++) {
        if (line_start && (*s == '.' || *s == '\''))
            fputs("\\&", out);
        line_start = *s == '\n';
        if (*s == '\\')
            fputs("\\e", out);
        else if (*s == '-')
            fputs("\\-", out);
        else
            fputc(*s, out);
    }
}

static void upper(const char *s, FILE *out)
{
    for (; *s; s++)
        fputc(*s >= 'a' && *s <= 'z' ? *s - 'a' + 'A' : *s, out);
}

/* The OPTIONS section: a subsection per group, an indented paragraph per option. */
static void man_options(const cli_command *c, FILE *out)
{
    fputs(".SH OPTIONS\n", out);
    for (int g = 0; g <= c->ngroups; g++) {
        const cli_group *grp = g < c->ngroups ? c->groups[g] : &common_group;
        fputs(".SS ", out);
        roff(grp->title ? grp->title : "options", out, 0);
        fputc('\n', out);
        int n;
        const cli_option *v = entries(grp, &n);
        for (int k = 0; k < n; k++) {
            const cli_option *o = &v[k];
            fputs(".TP\n", out);
            if (o->short_name)
                fprintf(out, "\\fB\\-%c\\fR, ", o->short_name);
            fputs("\\fB", out);
            roff(o->name, out, 0);
            fputs("\\fR", out);
            if (o->arg) {
                fputs(" \\fI", out);
                roff(o->arg, out, 0);
                fputs("\\fR", out);
            }
            fputc('\n', out);
            /* Continuation lines are one sentence in the man page. */
            char *h = strdup(o->help);
            if (h) {
                for (char *q = h; *q; q++)
                    if (*q == '\n')
                        *q = ' ';
                roff(h, out, 1);
                free(h);
            }
            fputc('\n', out);
        }
    }
}

void cli_man(const cli_command *c, const char *version, const char *see_also, FILE *out)
{
    char page[64];
    if (c->name)
        snprintf(page, sizeof page, "%s-%s", c->tool, c->name);
    else
        snprintf(page, sizeof page, "%s", c->tool);
    /* No date: the page is generated at build time and must not change between builds. */
    fputs(".TH ", out);
    upper(page, out);
    fprintf(out, " 1 \"\" \"brdfit %s\" \"brdfit manual\"\n.SH NAME\n", version);
    roff(page, out, 0);
    fputs(" \\- ", out);
    roff(c->summary, out, 0);
    fputs("\n.SH SYNOPSIS\n.B ", out);
    char title[64];
    roff(cli_title(c, title, sizeof title), out, 0);
    fputc('\n', out);
    roff(c->synopsis, out, 1);
    fputs("\n.SH DESCRIPTION\n", out);
    char first[512];
    snprintf(first, sizeof first, "%c%s.",
             c->summary[0] >= 'a' && c->summary[0] <= 'z' ? c->summary[0] - 'a' + 'A' : c->summary[0], c->summary + 1);
    roff(first, out, 1);
    fputc('\n', out);
    if (c->description) { /* paragraphs: a blank line becomes .PP */
        const char *p = c->description;
        while (*p) {
            const char *end = strstr(p, "\n\n");
            size_t len = end ? (size_t)(end - p) : strlen(p);
            char *para = strndup(p, len);
            if (para) {
                fputs(".PP\n", out);
                roff(para, out, 1);
                fputc('\n', out);
                free(para);
            }
            p += len;
            while (*p == '\n')
                p++;
        }
    }
    man_options(c, out);
    fputs(".SH EXIT STATUS\n0: done; 1: a failure (bad data, a failed fit, an output that cannot be "
          "written); 2: bad usage (options, model names, parameters).\n",
          out);
    if (see_also && *see_also) {
        fputs(".SH SEE ALSO\n", out);
        roff(see_also, out, 1);
        fputc('\n', out);
    }
}

/* ---- bash completion --------------------------------------------------------------- */

/* What completes an option's value: its declared kind, or the choices its value name
 * lists ("keep|drop|clamp"; not "N|all", which holds a placeholder). */
static const char *value_kind(const cli_option *o)
{
    if (o->complete)
        return o->complete;
    if (!o->arg || !strchr(o->arg, '|'))
        return NULL;
    for (const char *p = o->arg; *p; p++)
        if (!((*p >= 'a' && *p <= 'z') || (*p >= '0' && *p <= '9') || *p == '_' || *p == '|'))
            return NULL;
    return o->arg;
}

static void words(const char *choices, FILE *out)
{
    for (const char *p = choices; *p; p++)
        fputc(*p == '|' ? ' ' : *p, out);
}

/* The case arms of one command: values after an option, then options or operands. */
static void completion_arms(const cli_command *c, const char *(*words_of)(const char *kind), const char *indent,
                            FILE *out)
{
    fprintf(out, "%scase $prev in\n", indent);
    for (int g = 0; g <= c->ngroups; g++) {
        const cli_group *grp = g < c->ngroups ? c->groups[g] : &common_group;
        int n;
        const cli_option *v = entries(grp, &n);
        for (int k = 0; k < n; k++) {
            const cli_option *o = &v[k];
            if (!o->arg)
                continue;
            const char *kind = value_kind(o);
            fprintf(out, "%s%s", indent, o->name);
            if (o->short_name)
                fprintf(out, "|-%c", o->short_name);
            if (!kind)
                fputs(") return ;;\n", out);
            else if (!strcmp(kind, "file"))
                fputs(") COMPREPLY=($(compgen -f -- \"$cur\")); return ;;\n", out);
            else if (!strcmp(kind, "dir"))
                fputs(") COMPREPLY=($(compgen -d -- \"$cur\")); return ;;\n", out);
            else {
                const char *named = words_of ? words_of(kind) : NULL; /* "model", "method": from a registry */
                fputs(") COMPREPLY=($(compgen -W \"", out);
                words(named ? named : kind, out);
                fputs("\" -- \"$cur\")); return ;;\n", out);
            }
        }
    }
    fprintf(out, "%sesac\n%sif [[ $cur == -* ]]; then\n%s    COMPREPLY=($(compgen -W \"", indent, indent, indent);
    for (int g = 0; g <= c->ngroups; g++) {
        const cli_group *grp = g < c->ngroups ? c->groups[g] : &common_group;
        int n;
        const cli_option *v = entries(grp, &n);
        for (int k = 0; k < n; k++) {
            fprintf(out, "%s%s", g || k ? " " : "", v[k].name);
            if (v[k].short_name)
                fprintf(out, " -%c", v[k].short_name);
        }
    }
    fprintf(out, "\" -- \"$cur\"))\n%selse\n%s    COMPREPLY=($(compgen %s -- \"$cur\"))\n%sfi\n", indent, indent,
            c->operands && !strcmp(c->operands, "dir") ? "-d"
            : c->operands                              ? "-f"
                                                       : "-W ''",
            indent);
}

void cli_completion(const cli_command *const *cmds, int n, const char *(*words_of)(const char *kind), FILE *out)
{
    const char *tool = cmds[0]->tool;
    char fn[64];
    snprintf(fn, sizeof fn, "_%s", tool);
    for (char *p = fn; *p; p++)
        if (*p == '-')
            *p = '_';
    fprintf(out, "# bash completion for %s, generated from its option tables. -*- shell-script -*-\n", tool);
    fprintf(out, "%s()\n{\n    local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}\n", fn);
    fputs("    COMPREPLY=()\n", out);
    if (!cmds[0]->name) {
        completion_arms(cmds[0], words_of, "    ", out);
    } else {
        fputs("    if [ \"$COMP_CWORD\" -eq 1 ]; then\n        COMPREPLY=($(compgen -W \"", out);
        for (int i = 0; i < n; i++)
            fprintf(out, "%s ", cmds[i]->name);
        fputs("help --help --version\" -- \"$cur\"))\n        return\n    fi\n", out);
        fputs("    case ${COMP_WORDS[1]} in\n", out);
        for (int i = 0; i < n; i++) {
            fprintf(out, "    %s)\n", cmds[i]->name);
            completion_arms(cmds[i], words_of, "        ", out);
            fputs("        ;;\n", out);
        }
        fputs("    help)\n        [ \"$COMP_CWORD\" -eq 2 ] && COMPREPLY=($(compgen -W \"", out);
        for (int i = 0; i < n; i++)
            fprintf(out, "%s%s", i ? " " : "", cmds[i]->name);
        fputs("\" -- \"$cur\"))\n        ;;\n    esac\n", out);
    }
    fprintf(out, "}\ncomplete -o filenames -F %s %s\n", fn, tool);
}
