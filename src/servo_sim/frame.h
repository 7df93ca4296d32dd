/* popc-servo-sim's view of Modbus frames (ADUs) beyond what libmodbus checks:
 * is a received request well formed, and the faults injected into a reply
 * frame. Private to the program. TCP frames start with the 7-byte MBAP
 * header (transaction id, protocol id, length, unit id: Modbus Messaging on
 * TCP/IP Implementation Guide V1.0b, 3.1.3); RTU frames with the slave address
 * and end with the CRC-16 (Modbus over Serial Line V1.02, 2.5.1.2). */
#ifndef POPC_SERVO_SIM_FRAME_H
#define POPC_SERVO_SIM_FRAME_H

#include <stdint.h>

/* The CRC-16 of an RTU frame (polynomial 0xA001 reflected, start 0xFFFF),
 * sent low byte first. */
uint16_t frame_crc16(const uint8_t *p, int n);

/* Whether a request that libmodbus accepted is a frame popc may send: for
 * TCP, protocol id 0, a length field equal to the bytes that follow it, the
 * drive's unit id; for both, a function code the drive implements. why gets
 * a short reason when it is not. */
int frame_request_ok(const uint8_t *q, int len, int tcp, int slave, const char **why);

/* Reply faults, applied to a built reply frame of n bytes in place. */
enum frame_fault {
	FRAME_WRONG_TID,      /* TCP: transaction id + 1 */
	FRAME_WRONG_PROTOCOL, /* TCP: protocol id = arg */
	FRAME_WRONG_LENGTH,   /* TCP: length field + 1 */
	FRAME_WRONG_UNIT,     /* TCP unit id, RTU slave address + 1 (RTU: CRC recomputed) */
};
void frame_apply_fault(uint8_t *buf, int n, int tcp, enum frame_fault f, long arg);

#endif
