/* JUnit XML for CI systems, written with libxml2's xmlTextWriter (escaping and
 * well-formedness are its job) into memory, then through a temporary file renamed into
 * place, so an interrupted run leaves no partial report. */
#include "brdfit/regress.h"
#include "base/sized.h"

#include <libxml/xmlwriter.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/io.h"
#include "brdfit/version.h"

static const xmlChar *X(const char *s)
{
    return (const xmlChar *)s;
}

/* Names, paths and messages from the baseline as XML 1.0 can hold them: control
 * characters and invalid UTF-8, which no escaping makes well-formed, written as a
 * terminal shows them (bf_printable_dup); libxml2 escapes the markup. */
static int attr(xmlTextWriterPtr w, const char *name, const char *value)
{
    char *v = bf_printable_dup(value);
    bf_status rc = v && xmlTextWriterWriteAttribute(w, X(name), X(v)) >= 0 ? 0 : -1;
    free(v);
    return rc;
}

static int text(xmlTextWriterPtr w, const char *s)
{
    char *t = bf_printable_dup(s);
    bf_status rc = t && xmlTextWriterWriteString(w, X(t)) >= 0 ? 0 : -1;
    free(t);
    return rc;
}

static int attr_int(xmlTextWriterPtr w, const char *name, int v)
{
    char buf[16];
    snprintf(buf, sizeof buf, "%d", v);
    return attr(w, name, buf);
}

static int attr_time(xmlTextWriterPtr w, double seconds)
{
    char buf[32];
    snprintf(buf, sizeof buf, "%.3f", seconds);
    return attr(w, "time", buf);
}

/* The diff lines (without their indent), one per line, as the element's text. */
static int problem(xmlTextWriterPtr w, const char *element, const char *message, const bf_regress_outcome *o)
{
    if (xmlTextWriterStartElement(w, X(element)) < 0 || attr(w, "message", message) != 0)
        return -1;
    for (int i = 0; i < o->nlines; i++) {
        const char *line = o->lines[i] + strspn(o->lines[i], " ");
        if ((i > 0 && xmlTextWriterWriteString(w, X("\n")) < 0) || text(w, line) != 0)
            return -1;
    }
    return xmlTextWriterEndElement(w) < 0 ? -1 : 0;
}

static int write_doc(xmlTextWriterPtr w, const bf_regress_baseline *b, const bf_regress_outcome *outs)
{
    int tests = 0, failures = 0, errors = 0;
    double seconds = 0.0;
    for (int i = 0; i < b->ncases; i++) {
        if (outs[i].status == BF_REGRESS_SKIPPED)
            continue;
        tests++;
        failures += outs[i].status == BF_REGRESS_FAIL;
        errors += outs[i].status == BF_REGRESS_ERROR;
        seconds += outs[i].seconds;
    }
    if (xmlTextWriterSetIndent(w, 1) < 0 || xmlTextWriterStartDocument(w, NULL, "UTF-8", NULL) < 0)
        return -1;
    for (int level = 0; level < 2; level++) {
        if (xmlTextWriterStartElement(w, X(level ? "testsuite" : "testsuites")) < 0)
            return -1;
        if ((level && attr(w, "name", "brdfit regress") != 0) || attr_int(w, "tests", tests) != 0 ||
            attr_int(w, "failures", failures) != 0 || attr_int(w, "errors", errors) != 0 || attr_time(w, seconds) != 0)
            return -1;
    }
    /* The build that ran the cases, as a property of the suite (JUnit's place for it). */
    if (xmlTextWriterStartElement(w, X("properties")) < 0 || xmlTextWriterStartElement(w, X("property")) < 0 ||
        attr(w, "name", "brdfit_version") != 0 || attr(w, "value", bf_version()) != 0 ||
        xmlTextWriterEndElement(w) < 0 || xmlTextWriterEndElement(w) < 0)
        return -1;
    for (int i = 0; i < b->ncases; i++) {
        /* The caller's array: its elements are its size apart (docs/api.md). */
        const bf_regress_outcome *o = (const bf_regress_outcome *)((const char *)outs + (size_t)i * outs->size);
        if (o->status == BF_REGRESS_SKIPPED)
            continue;
        if (xmlTextWriterStartElement(w, X("testcase")) < 0 || attr(w, "name", b->cases[i].name) != 0 ||
            attr(w, "classname", b->path) != 0 || attr_time(w, o->seconds) != 0)
            return -1;
        if (o->status == BF_REGRESS_FAIL) {
            char message[64];
            snprintf(message, sizeof message, "%d value%s differ%s from the baseline", o->nlines,
                     o->nlines == 1 ? "" : "s", o->nlines == 1 ? "s" : "");
            if (problem(w, "failure", message, o) != 0)
                return -1;
        } else if (o->status == BF_REGRESS_ERROR) {
            if (problem(w, "error", o->nlines ? o->lines[0] : "the case could not run", o) != 0)
                return -1;
        }
        if (o->nwarnings > 0) { /* what to doubt in the fit, pass or fail */
            if (xmlTextWriterStartElement(w, X("system-out")) < 0)
                return -1;
            for (int k = 0; k < o->nwarnings; k++)
                if (xmlTextWriterWriteString(w, X("warning: ")) < 0 || text(w, o->warnings[k]) != 0 ||
                    xmlTextWriterWriteString(w, X("\n")) < 0)
                    return -1;
            if (xmlTextWriterEndElement(w) < 0)
                return -1;
        }
        if (xmlTextWriterEndElement(w) < 0)
            return -1;
    }
    return xmlTextWriterEndDocument(w) < 0 ? -1 : 0; /* closes every open element */
}

bf_status bf_regress_write_junit(const bf_regress_baseline *b, const bf_regress_outcome *outs, const char *path,
                                 bf_error *err)
{
    if (b->ncases > 0 && bf_sized_check(outs, sizeof *outs, "bf_regress_outcome", err) != BF_OK)
        return BF_ERR_ARG;
    xmlBufferPtr buf = xmlBufferCreate();
    xmlTextWriterPtr w = buf ? xmlNewTextWriterMemory(buf, 0) : NULL;
    if (!w) {
        xmlBufferFree(buf);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    }
    int bad = write_doc(w, b, outs);
    xmlFreeTextWriter(w); /* flushes into buf */
    if (bad) {
        xmlBufferFree(buf);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory writing the JUnit XML", path);
    }
    bf_outfile f;
    bf_status rc = bf_outfile_open(&f, path, err);
    if (rc == BF_OK) {
        fwrite(xmlBufferContent(buf), 1, (size_t)xmlBufferLength(buf), f.fp);
        rc = bf_outfile_commit(&f, err);
    }
    xmlBufferFree(buf);
    return rc;
}
