/* Internal: what the writers of bf_photo_write share (photo_write.c, photo_gltf.c). */
#ifndef BF_PHOTO_OUTPUTS_H
#define BF_PHOTO_OUTPUTS_H

#include "brdfit/image.h"
#include "brdfit/photo.h"
#include "io/out_folder.h"

/* An image into the folder being built (bf_image_write's formats and flags). Inline: both
 * writers use it, so it belongs to neither. */
static inline bf_status photo_write_image(const bf_out_folder *f, const char *name, int w, int h, int ch,
                                          const float *px, unsigned flags, bf_error *err)
{
    char path[4200];
    bf_status rc = bf_out_folder_path(f, name, path, sizeof path, err);
    return rc != BF_OK ? rc : bf_image_write(path, BF_IMAGE_BY_NAME, w, h, ch, px, flags, err);
}
/* The gltf model's fit as a textured glTF material on a quad the size of the image:
 * material.gltf, base_color.png (sRGB), metallic_roughness.png (G roughness, B metallic)
 * and normal.png (tangent space: the camera frame of a flat sample). */
bf_status photo_write_gltf(const bf_out_folder *f, const bf_photo_result *r, bf_error *err);

#endif
