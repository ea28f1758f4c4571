/* SIGINT as the cancel flag of bf_compare_run (brdfit compare, brdfit batch): the first
 * SIGINT sets the flag, so no new fit starts and running fits finish; a second ends the
 * process at once (the default action, restored by the first). */
#ifndef BRDFIT_INTERRUPT_H
#define BRDFIT_INTERRUPT_H

#include <signal.h>

/* Read by the fitting threads (bf_compare_run_options.cancel). */
extern volatile sig_atomic_t interrupt_flag;

/* Sets the flag (the handler; also a command that must stop its run for another reason). */
void interrupt_raise(void);
/* Clears the flag and installs the handler; *old keeps the previous action. */
void interrupt_catch(struct sigaction *old);
/* Puts the previous action back. */
void interrupt_release(const struct sigaction *old);

#endif
