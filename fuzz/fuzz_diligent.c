/* Image stacks (photo.h): DiLiGenT folders as bf_stack_read reads them. The input is
 * split at its NUL bytes (0x00), which no part then holds:
 *
 *   FILENAMES \0 DIRECTIONS \0 INTENSITIES [\0 MASK]
 *
 * written as filenames.txt, light_directions.txt and light_intensities.txt in the folder
 * dl/ of the scratch folder; a file whose part is missing (fewer NUL bytes) is absent.
 * With a third NUL byte the folder has a mask.png: a link to the scratch image that MASK
 * names (big.png: a mask of another size), else to m.png. The folder also holds links
 * to the scratch images of fuzz_stack.c (a.png ... big.png), so filenames.txt names them
 * as they are.
 *
 * A stack read is checked as fuzz_stack.c checks every stack (the images' headers read
 * again, unit directions, positive finite intensities) and as the DiLiGenT layout has it
 * (docs/images.md): one image per non-blank line of filenames.txt, the line's name (cut
 * of white space) in the folder, directional lights, linear codes, saturation at the
 * largest code, automatic scale, orthographic camera of pixel size 1, the mask when
 * mask.png exists. */
#define FUZZ_STACK_COMMON_ONLY
#include "fuzz_stack.c"

#include <ctype.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *const text_files[3] = {"filenames.txt", "light_directions.txt", "light_intensities.txt"};
static char folder[512];

/* folder/name */
static const char *in_folder(const char *name)
{
    static char path[1024];
    snprintf(path, sizeof path, "%s/%s", folder, name);
    return path;
}

static void remove_folder(void)
{
    for (int i = 0; i < 3; i++)
        unlink(in_folder(text_files[i]));
    unlink(in_folder("mask.png"));
    for (int i = 0; i < NSCRATCH; i++)
        unlink(in_folder(scratch_images[i].name));
    rmdir(folder);
}

/* The images, the folder and the links to them (once per process). */
static void make_folder(void)
{
    if (folder[0])
        return;
    make_images(); /* the scratch folder is made first: remove_folder runs before its removal */
    snprintf(folder, sizeof folder, "%s", fuzz_path("dl"));
    if (mkdir(folder, 0700) != 0)
        fuzz_fail("cannot make %s", folder);
    atexit(remove_folder);
    for (int i = 0; i < NSCRATCH; i++)
        if (symlink(fuzz_path(scratch_images[i].name), in_folder(scratch_images[i].name)) != 0)
            fuzz_fail("cannot link %s", in_folder(scratch_images[i].name));
}

/* The part of the input in [p, end) as the file name in the folder (fuzz_write's path). */
static void write_part(int i, const uint8_t *p, const uint8_t *end)
{
    char name[64];
    snprintf(name, sizeof name, "dl/%s", text_files[i]);
    fuzz_write(name, p, (size_t)(end - p));
}

/* The stack read against the folder's filenames.txt (text: NUL-terminated). */
static void check_diligent(const bf_stack *s, char *text, int has_mask)
{
    if (s->layout != BF_STACK_DILIGENT)
        fuzz_fail("a DiLiGenT folder read as layout %d", (int)s->layout);
    if (strcmp(s->path, folder) != 0)
        fuzz_fail("a stack read from %s says it is %s", folder, s->path);
    int k = 0;
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        char *e = line + strlen(line);
        while (e > line && isspace((unsigned char)e[-1]))
            *--e = '\0';
        while (isspace((unsigned char)*line))
            line++;
        if (!*line)
            continue;
        if (k >= s->nimages)
            fuzz_fail("%d images read from more lines ('%s')", s->nimages, line);
        const char *want = line[0] == '/' ? line : in_folder(line);
        if (strcmp(s->images[k].file, want) != 0)
            fuzz_fail("image %d: '%s' read as '%s'", k, want, s->images[k].file);
        if (s->images[k].point || s->images[k].exposure != 1.0)
            fuzz_fail("image %d: a point light or an exposure (%g)", k, s->images[k].exposure);
        k++;
    }
    if (k != s->nimages)
        fuzz_fail("%d images read from %d lines", s->nimages, k);
    if (s->transfer != BF_TRANSFER_LINEAR || s->black_level != 0.0 || s->scale != 0.0)
        fuzz_fail("transfer %d, black level %g, scale %g", (int)s->transfer, s->black_level, s->scale);
    if (s->saturation != (s->is_float ? INFINITY : 1.0))
        fuzz_fail("saturation %g of %s images", s->saturation, s->is_float ? "float" : "integer");
    if (s->camera.type != BF_CAMERA_ORTHOGRAPHIC || s->camera.pixel_size != 1.0)
        fuzz_fail("camera type %d, pixel size %g", (int)s->camera.type, s->camera.pixel_size);
    if (has_mask != (s->mask != NULL) || (s->mask && strcmp(s->mask, in_folder("mask.png")) != 0))
        fuzz_fail("mask.png %s, the stack's mask %s", has_mask ? "there" : "absent", s->mask ? s->mask : "(none)");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    make_folder();
    /* The parts: up to 3 ending at a NUL byte, the last one at the end of the input. */
    const uint8_t *part[4], *p = data, *end = data + size;
    size_t len[4];
    int nparts = 0;
    while (nparts < 4) {
        const uint8_t *nul = nparts < 3 && p < end ? memchr(p, 0, (size_t)(end - p)) : NULL;
        part[nparts] = p;
        len[nparts++] = (size_t)((nul ? nul : end) - p);
        if (!nul)
            break;
        p = nul + 1;
    }
    for (int i = 0; i < 3; i++) {
        if (i < nparts)
            write_part(i, part[i], part[i] + len[i]);
        else
            unlink(in_folder(text_files[i]));
    }
    unlink(in_folder("mask.png"));
    const int mask = nparts == 4;
    if (mask) {
        const char *target = fuzz_path("m.png");
        for (int i = 0; i < NSCRATCH; i++)
            if (len[3] == strlen(scratch_images[i].name) && !memcmp(part[3], scratch_images[i].name, len[3]))
                target = fuzz_path(scratch_images[i].name);
        if (symlink(target, in_folder("mask.png")) != 0)
            fuzz_fail("cannot link %s", in_folder("mask.png"));
    }
    bf_error err;
    bf_stack *s = NULL;
    int rc = bf_stack_read(folder, &s, &err);
    fuzz_check_result(rc, &err, s);
    if (s) {
        check_stack(s);
        char *text = malloc(len[0] + 1);
        if (!text)
            fuzz_fail("out of memory");
        memcpy(text, part[0], len[0]);
        text[len[0]] = '\0';
        check_diligent(s, text, mask);
        free(text);
    }
    bf_stack_free(s);
    return 0;
}
