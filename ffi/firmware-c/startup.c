/* Start-up of the C firmware on the Cortex-M4F (mps2-an386): the vector
 * table, and a reset handler that copies .data, clears .bss, turns the FPU
 * on (the hard-float ABI uses it from the first instruction of main),
 * opens newlib's semihosting handles and calls main. */

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _stack_top;
extern int main(void);
extern void initialise_monitor_handles(void);

void reset_handler(void) {
  memcpy(&_sdata, &_sidata, (size_t)((char *)&_edata - (char *)&_sdata));
  memset(&_sbss, 0, (size_t)((char *)&_ebss - (char *)&_sbss));
  /* CPACR: full access to CP10 and CP11 (the FPU). */
  *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
  __asm volatile("dsb\n\tisb");
  initialise_monitor_handles();
  exit(main());
}

static void hang(void) {
  for (;;) {
  }
}

/* Initial stack pointer, reset, and the fault handlers (a fault hangs:
 * the test's timeout reports it). */
__attribute__((section(".vectors"), used)) static void (*const vectors[16])(void) = {
    (void (*)(void))&_stack_top, reset_handler, hang, hang, hang, hang, hang, 0, 0, 0, 0, hang,
    hang, 0, hang, hang,
};

/* newlib's exit runs the .fini_array through _fini (crtn.o's, which
 * -nostartfiles leaves out): nothing to do here. */
void _init(void) {}
void _fini(void) {}
