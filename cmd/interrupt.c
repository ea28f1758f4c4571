/* SIGINT as a cancel flag (interrupt.h). */
#include "interrupt.h"

#include <string.h>

volatile sig_atomic_t interrupt_flag;

/* Stored atomically where the compiler can, as the library loads it (compare_run.c). */
void interrupt_raise(void)
{
#if defined(__GNUC__)
    __atomic_store_n(&interrupt_flag, 1, __ATOMIC_RELAXED);
#else
    interrupt_flag = 1;
#endif
}

static void on_sigint(int sig)
{
    (void)sig;
    interrupt_raise();
}

void interrupt_catch(struct sigaction *old)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigint;
    sa.sa_flags = SA_RESETHAND; /* a second ^C ends the process */
    sigemptyset(&sa.sa_mask);
    interrupt_flag = 0;
    sigaction(SIGINT, &sa, old);
}

void interrupt_release(const struct sigaction *old)
{
    sigaction(SIGINT, old, NULL);
}
