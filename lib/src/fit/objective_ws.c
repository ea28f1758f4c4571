/* The objective's workspaces (objective_ws.h): a free list under a lock, buffers grown
 * on demand and kept until the list ends. */
#include "objective_ws.h"

#include <stdlib.h>

bf_obj_ws_list *bf_obj_ws_list_new(void)
{
    bf_obj_ws_list *l = calloc(1, sizeof *l);
    if (l && pthread_mutex_init(&l->lock, NULL) != 0) {
        free(l);
        l = NULL;
    }
    return l;
}

bf_obj_ws *bf_obj_ws_get(bf_obj_ws_list *l)
{
    pthread_mutex_lock(&l->lock);
    bf_obj_ws *w = l->free_list;
    if (w)
        l->free_list = w->next_free;
    else if ((w = calloc(1, sizeof *w))) {
        w->next_all = l->all;
        l->all = w;
    }
    pthread_mutex_unlock(&l->lock);
    return w;
}

void bf_obj_ws_put(bf_obj_ws_list *l, bf_obj_ws *w)
{
    if (!w)
        return;
    pthread_mutex_lock(&l->lock);
    w->next_free = l->free_list;
    l->free_list = w;
    pthread_mutex_unlock(&l->lock);
}

void *bf_obj_ws_buf(bf_obj_ws *w, int k, size_t bytes)
{
    if (bytes == 0)
        bytes = 1;
    if (w->cap[k] < bytes) { /* the contents need not survive: no realloc copy */
        free(w->buf[k]);
        w->cap[k] = 0;
        if (!(w->buf[k] = malloc(bytes)))
            return NULL;
        w->cap[k] = bytes;
    }
    return w->buf[k];
}

void bf_obj_ws_list_free(bf_obj_ws_list *l)
{
    if (!l)
        return;
    for (bf_obj_ws *w = l->all, *nx; w; w = nx) {
        nx = w->next_all;
        for (int k = 0; k < BF_WS_NBUF; k++)
            free(w->buf[k]);
        free(w);
    }
    pthread_mutex_destroy(&l->lock);
    free(l);
}
