/* SPDX-License-Identifier: MIT */
/* The built-in vocabulary (vocabulary.h) as read-only data: the bytes of DSM_VOCABULARY_FILE. */
  .section .rodata
  .balign 16
  .global dsm_vocabulary_begin
  .global dsm_vocabulary_end
dsm_vocabulary_begin:
  .incbin DSM_VOCABULARY_FILE
dsm_vocabulary_end:
  .byte 0
  .section .note.GNU-stack,"",%progbits
