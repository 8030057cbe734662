//! The flash store against sequential-storage's RAM model of a NOR flash (4-byte words, pages
//! of 512 bytes, each word written once between erases, power cuts after N bytes): a certified
//! `PARAM_SET` survives a restart, damage or another table restores the flight file and says
//! so, and a power cut at any byte of any save restarts on a whole certified set. Given/when/
//! then, on the host.
#![cfg(not(feature = "uncertified-paper"))] // the default flight file's x500

use embassy_futures::block_on;
use sequential_storage::mock_flash::{MockFlashBase, WriteCountCheck};

use super::*;
use crate::link;
use crate::params::ParamError;

type Flash = MockFlashBase<4, 4, 128>;

fn blank() -> Flash {
    Flash::new(WriteCountCheck::OnceOnly, None, true)
}

fn store(flash: Flash) -> FlashStore<Flash> {
    FlashStore::new(flash, Flash::FULL_FLASH_RANGE).unwrap()
}

/// A vehicle on the build's flight file that took `POS_KF = kf` by a PARAM_SET over the link.
fn tuned(kf: f32) -> FlightPipeline {
    let mut p = FlightPipeline::new(&FlightConfig::built()).unwrap();
    let mut m = [0u8; link::MAX_FRAME];
    let set = crate::ground_station::param_set("POS_KF", kf);
    let n = link::encode(&set, 255, 190, 0, &mut m);
    p.on_link_bytes(&m[..n], 0);
    assert_eq!(p.config().gains.position.kf, kf, "PARAM_SET refused");
    p
}

fn save(flash: Flash, config: &FlightConfig) -> Flash {
    let mut s = store(flash);
    block_on(s.save(config)).unwrap();
    s.into_flash()
}

/// A restart: a fresh pipeline on the flight file, restored from `flash`.
fn boot(flash: Flash) -> (FlightPipeline, Restore, Flash) {
    let mut p = FlightPipeline::new(&FlightConfig::built()).unwrap();
    let mut s = store(flash);
    let r = block_on(s.restore(&mut p));
    (p, r, s.into_flash())
}

fn certified(p: &FlightPipeline) -> bool {
    let r = p.boot_report();
    r.gate.is_ok() && r.certificate.violations().next().is_none()
}

fn kf_built() -> f32 {
    FlightConfig::built().gains.position.kf
}

/// Given a vehicle that took a certified PARAM_SET and saved it, when it restarts from the same
/// flash, then the new value is flown with its certificate (the boot banner's data), not the
/// flight file's; and a blank flash boots on the flight file.
#[test]
fn a_saved_param_set_survives_a_restart() {
    let (p, r, _) = boot(blank());
    assert_eq!(r, Restore::Empty);
    assert_eq!(*p.config(), FlightConfig::built());

    let a = tuned(0.8 * kf_built());
    let saved = save(blank(), a.config());
    // A save erases only when a page is full (on the F405 a sector erase stalls the CPU).
    assert_eq!(
        blank()
            .stats_snapshot()
            .compare_to(saved.stats_snapshot())
            .erases,
        0
    );
    let (b, r, flash) = boot(saved);
    assert_eq!(r, Restore::Restored { values: COUNT });
    assert_eq!(b.config(), a.config());
    assert_eq!(b.boot_report(), a.boot_report());
    assert_ne!(b.boot_report(), p.boot_report());
    // Restoring does not consume the record: the next restart flies it again.
    assert_eq!(boot(flash).1, Restore::Restored { values: COUNT });
}

/// Given a saved set, when any one written byte of the flash is flipped, then the restart flies
/// either the saved set (the byte was not part of the record's checked data) or the flight file
/// with the fault named and the store erased, so the restart after it is clean.
#[test]
fn a_corrupted_store_restores_the_flight_file_and_is_erased() {
    let a = tuned(0.8 * kf_built());
    let saved = save(blank(), a.config());
    let written: Vec<usize> = (0..saved.as_bytes().len())
        .filter(|&i| saved.as_bytes()[i] != 0xFF)
        .collect();
    assert!(written.len() > RECORD_LEN);
    let mut corrupt = 0;
    for &i in &written {
        let mut flash = saved.clone();
        flash.as_bytes_mut()[i] ^= 0x10;
        let (p, r, flash) = boot(flash);
        match r {
            Restore::Restored { .. } => assert_eq!(p.config(), a.config(), "byte {i}"),
            Restore::Defaults { fault, erased } => {
                assert!(erased, "byte {i}");
                assert!(
                    matches!(fault, Fault::Corrupt | Fault::OtherTable),
                    "byte {i}: {fault:?}"
                );
                assert_eq!(*p.config(), FlightConfig::built(), "byte {i}");
                assert!(flash.as_bytes().iter().all(|&b| b == 0xFF));
                assert_eq!(boot(flash).1, Restore::Empty);
                corrupt += 1;
            }
            Restore::Empty => panic!("byte {i}: a written store read as blank"),
        }
        assert!(certified(&p));
    }
    // Every byte of the record's data is under its CRC.
    assert!(corrupt >= RECORD_LEN, "{corrupt} of {}", written.len());
}

/// Given intact records the build must not take (another table's hash, another format, a
/// stored NaN, a set-up that breaks Theorem 2), when the vehicle restarts, then it flies the
/// flight file, names why, and erases the store.
#[test]
fn records_of_another_table_or_uncertified_restore_the_flight_file() {
    let raw = |record: &[u8]| {
        let mut s = store(blank());
        block_on(s.map.store_item(&mut s.buf.0, &KEY, &record)).unwrap();
        s.into_flash()
    };
    let mut record = [0u8; RECORD_LEN];
    record[..4].copy_from_slice(&FORMAT.to_le_bytes());
    record[4..8].copy_from_slice(&(TABLE_HASH ^ 1).to_le_bytes());
    let expect_defaults = |flash: Flash, fault: Fault| {
        let (p, r, flash) = boot(flash);
        assert_eq!(
            r,
            Restore::Defaults {
                fault,
                erased: true
            }
        );
        assert_eq!(*p.config(), FlightConfig::built());
        assert_eq!(boot(flash).1, Restore::Empty);
    };
    expect_defaults(raw(&record), Fault::OtherTable);
    record[4..8].copy_from_slice(&TABLE_HASH.to_le_bytes());
    record[..4].copy_from_slice(&(FORMAT + 1).to_le_bytes());
    expect_defaults(raw(&record), Fault::OtherTable);
    expect_defaults(raw(&record[..RECORD_LEN - 4]), Fault::OtherTable);

    let mut c = FlightConfig::built();
    c.gains.position.kp = f32::NAN;
    expect_defaults(
        save(blank(), &c),
        Fault::Refused(RestoreError {
            name: Some("POS_KP"),
            refusal: ParamRefusal::Value(ParamError::NotFinite),
        }),
    );

    // Each value in range, the set-up not certified: a yaw torque limit between Assumption 1's
    // and Theorem 2's bounds.
    let boot_report = FlightPipeline::new(&FlightConfig::built())
        .unwrap()
        .boot_report();
    let rhs_of = |name: &str| {
        boot_report
            .certificate
            .conditions
            .iter()
            .find(|k| k.name == name)
            .unwrap()
            .rhs
    };
    let mut c = FlightConfig::built();
    c.limits.torque_max.z =
        0.5 * (rhs_of("assumption1.torque_max_yaw") + rhs_of("theorem2.torque_max_yaw"));
    let (p, r, _) = boot(save(blank(), &c));
    match r {
        Restore::Defaults {
            fault:
                Fault::Refused(RestoreError {
                    name: None,
                    refusal: ParamRefusal::Condition(f),
                }),
            erased: true,
        } => assert_eq!(f.condition, "theorem2.torque_max_yaw"),
        other => panic!("{other:?}"),
    }
    assert!(certified(&p));
}

/// Given a history of saves alternating two certified sets (enough to fill pages, so some saves
/// migrate and erase a page), when the power is cut after every possible number of bytes
/// written or erased by each save, then the restart flies the set before that save or the one
/// it was writing — never a mix, never an unreadable store — and the next save and restart work.
#[test]
fn a_power_cut_at_any_byte_of_a_save_restarts_on_a_whole_certified_set() {
    let sets = [tuned(0.8 * kf_built()), tuned(0.9 * kf_built())];
    let configs = [*sets[0].config(), *sets[1].config()];
    assert_ne!(configs[0], configs[1]);
    let mut before = blank();
    let (mut old_seen, mut new_seen, mut erases_cut) = (0, 0, 0);
    for j in 0..16 {
        let old = (j > 0).then(|| configs[(j + 1) % 2]);
        let new = configs[j % 2];
        let mut n = 0;
        loop {
            let mut flash = before.clone();
            flash.bytes_until_shutoff = Some(n);
            let stats = flash.stats_snapshot();
            let mut s = store(flash);
            let done = block_on(s.save(&new)).is_ok();
            let mut flash = s.into_flash();
            if !done && stats.compare_to(flash.stats_snapshot()).erases > 0 {
                erases_cut += 1;
            }
            flash.bytes_until_shutoff = None;
            let (p, r, flash) = boot(flash);
            assert!(certified(&p), "save {j}, cut at {n}");
            match r {
                Restore::Restored { values } => {
                    assert_eq!(values, COUNT);
                    if Some(*p.config()) == old {
                        old_seen += 1;
                    } else {
                        assert_eq!(*p.config(), new, "save {j}, cut at {n}: a mixed set");
                        new_seen += 1;
                    }
                }
                // Only a first save, cut, may leave nothing to restore.
                Restore::Empty | Restore::Defaults { .. } => {
                    assert_eq!(old, None, "save {j}, cut at {n}: {r:?}");
                    assert_eq!(*p.config(), FlightConfig::built());
                }
            }
            // The store stays usable: the save is redone and restored.
            let (p, r, _) = boot(save(flash, &new));
            assert_eq!(
                r,
                Restore::Restored { values: COUNT },
                "save {j}, cut at {n}"
            );
            assert_eq!(*p.config(), new);
            if done {
                break;
            }
            n += 1;
        }
        before = save(before, &new);
    }
    assert!(old_seen > 0 && new_seen > 0);
    assert!(erases_cut > 0, "no save erased a page: fill more");
}

/// Given a saved tuned set, when the store is cleared (the reset of `MAV_CMD_PREFLIGHT_STORAGE`,
/// one record, no erase), then the restart flies the flight file and reports nothing stored;
/// with the power cut at any byte of the clear, the restart flies the tuned set or the flight
/// file, and a later save is restored.
#[test]
fn a_cleared_store_restarts_on_the_flight_file() {
    let a = tuned(0.8 * kf_built());
    let saved = save(blank(), a.config());
    let mut n = 0;
    loop {
        let mut flash = saved.clone();
        flash.bytes_until_shutoff = Some(n);
        let stats = flash.stats_snapshot();
        let mut s = store(flash);
        let done = block_on(s.clear()).is_ok();
        let mut flash = s.into_flash();
        assert_eq!(stats.compare_to(flash.stats_snapshot()).erases, 0);
        flash.bytes_until_shutoff = None;
        let (p, r, flash) = boot(flash);
        match r {
            Restore::Restored { .. } => {
                assert!(!done);
                assert_eq!(p.config(), a.config(), "cut at {n}");
            }
            Restore::Empty => assert_eq!(*p.config(), FlightConfig::built(), "cut at {n}"),
            Restore::Defaults { .. } => panic!("cut at {n}: {r:?}"),
        }
        assert!(certified(&p));
        assert_eq!(
            boot(save(flash, a.config())).1,
            Restore::Restored { values: COUNT }
        );
        if done {
            assert_eq!(r, Restore::Empty);
            break;
        }
        n += 1;
    }
}
