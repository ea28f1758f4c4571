/* Internal: a fit whose channels are independent problems, run as one fit per channel
 * (docs/fitting.md, "Independent channels"). A family declares that channel c's value
 * depends on channel c's colour entries and the scalars alone (bf_family's
 * channels_independent); with no free scalar the C channels then share nothing, and C
 * fits of P/C parameters each find what one of P would, at a fraction of the cost (the
 * search's work grows faster than linearly in the parameters, and one trust region for
 * all channels moves as slowly as the slowest). fit.c merges the channels' results and
 * computes the metrics, standard errors and warnings once, over all channels, as any
 * fit does. */
#ifndef BF_FIT_CHANNELS_H
#define BF_FIT_CHANNELS_H

#include "fit_impl.h"
#include "objective_state.h"

/* 1 when a fit of objective obj runs channel by channel: its family declares independent
 * channels, it has more than one channel, and every scalar entry is fixed. */
int bf_fit_channels_separable(const bf_objective *obj);

/* Channel c of s as a sample set of its own (*out, freed with bf_samples_free): the
 * same directions (or MERL cells), weights and scene weights, channel c's values, name
 * and wavelength. */
bf_status bf_fit_channels_samples(const bf_samples *s, int c, bf_samples **out, bf_error *err);

/* Channel c's fit options in oc (a copy of o, its overrides pointing at room for o's and
 * its start, when o has one, at room for m1's values): the overrides of every channel and
 * channel c's renamed to the channel's only one, and o->start's entries of channel c and
 * the scalars. m: o's model (C channels), m1: the same spec for one channel. The seed
 * stays o's: channel c's fit is that of channel c's data alone. */
bf_status bf_fit_channels_options(const bf_fit_options *o, const bf_model *m, const bf_model *m1, int c,
                                  bf_fit_options *oc);

/* Model entry k1 of a channel's model (1 channel) -> the entry of channel c in the
 * model of C channels (same spec). */
int bf_fit_channels_entry(const bf_model *m, const bf_model *m1, int c, int k1);

/* Writes the channels' results into r (its model and arrays made, C channels): the
 * values, inactive entries and their gates; the solution (costs, iterations,
 * evaluations and seconds summed; the worst stop; usable when every channel's is); the
 * starts and candidates each channel ran (the option's), the least sure channel's starts
 * at the best, the screen's and presolve's work summed; ok when every channel's is. */
void bf_fit_channels_merge(const bf_fit_result *ch, int C, bf_fit_result *r);

/* The channels' own search warnings (failed, solver limit, one start) into r, each
 * prefixed with its channel's name: what the merged figures cannot say. */
void bf_fit_channels_warn(const bf_fit_result *ch, const bf_samples *s, bf_fit_result *r);

#endif
