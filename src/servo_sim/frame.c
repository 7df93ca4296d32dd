/* popc-servo-sim's frame checks and reply faults (frame.h). */
#include "frame.h"

#include <modbus.h>

uint16_t frame_crc16(const uint8_t *p, int n)
{
	uint16_t crc = 0xFFFF;
	for (int i = 0; i < n; i++) {
		crc ^= p[i];
		for (int b = 0; b < 8; b++)
			crc = (crc & 1) ? (uint16_t)((crc >> 1) ^ 0xA001) : (uint16_t)(crc >> 1);
	}
	return crc;
}

static int known_function(int fc)
{
	switch (fc) {
	case MODBUS_FC_READ_COILS:
	case MODBUS_FC_READ_DISCRETE_INPUTS:
	case MODBUS_FC_READ_HOLDING_REGISTERS:
	case MODBUS_FC_READ_INPUT_REGISTERS:
	case MODBUS_FC_WRITE_SINGLE_COIL:
	case MODBUS_FC_WRITE_SINGLE_REGISTER:
	case MODBUS_FC_WRITE_MULTIPLE_COILS:
	case MODBUS_FC_WRITE_MULTIPLE_REGISTERS:
	case MODBUS_FC_WRITE_AND_READ_REGISTERS:
		return 1;
	default:
		return 0;
	}
}

int frame_request_ok(const uint8_t *q, int len, int tcp, int slave, const char **why)
{
	int hl = tcp ? 7 : 1;
	if (len < hl + 1) {
		*why = "shorter than a header and a function code";
		return 0;
	}
	if (tcp) {
		if (q[2] != 0 || q[3] != 0) {
			*why = "protocol id is not 0";
			return 0;
		}
		if ((q[4] << 8 | q[5]) != len - 6) {
			*why = "MBAP length field does not match the frame";
			return 0;
		}
		if (q[6] != slave) {
			*why = "unit id is not the drive's";
			return 0;
		}
	}
	if (!known_function(q[hl])) {
		*why = "unknown function code";
		return 0;
	}
	return 1;
}

void frame_apply_fault(uint8_t *buf, int n, int tcp, enum frame_fault f, long arg)
{
	if (n < (tcp ? 8 : 4))
		return;
	switch (f) {
	case FRAME_WRONG_TID: {
		uint16_t tid = (uint16_t)((buf[0] << 8 | buf[1]) + 1);
		buf[0] = (uint8_t)(tid >> 8);
		buf[1] = (uint8_t)tid;
		break;
	}
	case FRAME_WRONG_PROTOCOL:
		buf[2] = (uint8_t)(arg >> 8);
		buf[3] = (uint8_t)arg;
		break;
	case FRAME_WRONG_LENGTH: {
		uint16_t l = (uint16_t)((buf[4] << 8 | buf[5]) + 1);
		buf[4] = (uint8_t)(l >> 8);
		buf[5] = (uint8_t)l;
		break;
	}
	case FRAME_WRONG_UNIT:
		if (tcp) {
			buf[6] = (uint8_t)(buf[6] + 1);
		} else {
			buf[0] = (uint8_t)(buf[0] + 1);
			uint16_t crc = frame_crc16(buf, n - 2);
			buf[n - 2] = (uint8_t)crc; /* low byte first */
			buf[n - 1] = (uint8_t)(crc >> 8);
		}
		break;
	}
}
